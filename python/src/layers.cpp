// Image <-> penumbra.Layers (see layers.h).
#include "layers.h"

#include <cstring>
#include <memory>
#include <vector>

#include <pybind11/numpy.h>

namespace py = pybind11;

namespace penumbra::python {
namespace {

// The EXR header attributes (SCENE_FORMAT.md "Output"; docs/design/contract-decisions.md for sampler and pieces), by
// their names without "penumbra:".
py::dict metaFromImage(const ImageMetadata& m) {
    py::dict meta;
    if (m.spp) meta["spp"] = *m.spp;
    if (m.seed) meta["seed"] = *m.seed;
    if (m.sampleOffset) meta["sample_offset"] = *m.sampleOffset;
    if (m.integrator) meta["integrator"] = *m.integrator;
    if (m.renderSeconds) meta["render_seconds"] = *m.renderSeconds;
    if (m.sampler) meta["sampler"] = *m.sampler;
    if (m.pieces) meta["pieces"] = formatSamplePieces(*m.pieces);
    return meta;
}

ImageMetadata metaFromPython(py::handle meta) {
    ImageMetadata m;
    if (meta.is_none()) return m;
    if (!py::isinstance<py::dict>(meta)) throw py::type_error("layers.meta must be a dict");
    for (auto item : py::reinterpret_borrow<py::dict>(meta)) {
        const std::string key = py::str(item.first);
        py::handle v = item.second;
        if (key == "spp") m.spp = v.cast<int>();
        else if (key == "seed") m.seed = v.cast<int>();
        else if (key == "sample_offset") m.sampleOffset = v.cast<int>();
        else if (key == "integrator") m.integrator = v.cast<std::string>();
        else if (key == "render_seconds") m.renderSeconds = v.cast<double>();
        else if (key == "sampler") m.sampler = v.cast<std::string>();
        else if (key == "pieces") {
            try {
                m.pieces = parseSamplePieces(v.cast<std::string>());
            } catch (const std::invalid_argument& e) {
                throw py::value_error("meta[\"pieces\"]: " + std::string(e.what()));
            }
        } else {
            throw py::value_error("unknown metadata key \"" + key +
                                  "\" (known: spp, seed, sample_offset, integrator, render_seconds, sampler, pieces)");
        }
    }
    return m;
}

// A float32 array of `shape` that owns `values` (moved, not copied).
py::array_t<float> ownedArray(std::vector<float>&& values, const std::vector<py::ssize_t>& shape) {
    auto owner = std::make_unique<std::vector<float>>(std::move(values));
    float* data = owner->data();
    // The capsule owns the vector from here on: the array frees it with its last reference.
    py::capsule free(owner.release(), [](void* p) { delete static_cast<std::vector<float>*>(p); });
    return py::array_t<float>(shape, data, free);
}

}  // namespace

py::object layersFromImage(Image&& image) {
    py::object layers = py::module_::import("penumbra").attr("Layers")();
    const py::ssize_t h = image.height, w = image.width;
    layers["rgb"] = ownedArray(std::move(image.rgb), {h, w, 3});
    layers.attr("meta") = metaFromImage(image.meta);
    return layers;
}

Image imageFromLayers(py::handle layers) {
    if (!py::isinstance<py::dict>(layers)) throw py::type_error("layers must be a dict of arrays (as render returns)");
    py::dict dict = py::reinterpret_borrow<py::dict>(layers);
    for (auto item : dict) {
        const std::string name = py::str(item.first);
        if (name != "rgb") throw py::value_error("unknown layer \"" + name + "\" (this version writes: rgb)");
    }
    if (!dict.contains("rgb")) throw py::value_error("layers without \"rgb\"");
    auto rgb = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(dict["rgb"]);
    if (!rgb || rgb.ndim() != 3 || rgb.shape(2) != 3 || rgb.shape(0) == 0 || rgb.shape(1) == 0)
        throw py::value_error("layers[\"rgb\"] must be an array of shape (height, width, 3)");
    Image image;
    image.height = uint32_t(rgb.shape(0));
    image.width = uint32_t(rgb.shape(1));
    image.rgb.resize(size_t(rgb.size()));
    std::memcpy(image.rgb.data(), rgb.data(), image.rgb.size() * sizeof(float));
    image.meta = metaFromPython(py::getattr(layers, "meta", py::none()));
    return image;
}

}  // namespace penumbra::python
