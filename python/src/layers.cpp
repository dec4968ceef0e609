// Image <-> penumbra.Layers (see layers.h).
#include "layers.h"

#include <cstring>
#include <memory>
#include <vector>

#include <pybind11/numpy.h>

#include "image/aov_channels.h"
#include "image/aov_false_color.h"

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

py::array_t<uint32_t> ownedIds(std::vector<uint32_t>&& values, const std::vector<py::ssize_t>& shape) {
    auto owner = std::make_unique<std::vector<uint32_t>>(std::move(values));
    uint32_t* data = owner->data();
    py::capsule free(owner.release(), [](void* p) { delete static_cast<std::vector<uint32_t>*>(p); });
    return py::array_t<uint32_t>(shape, data, free);
}

// An AOV layer's array shape: (h, w) for one channel (depth, the ids), else (h, w, channels).
std::vector<py::ssize_t> layerShape(const AovLayer& layer, py::ssize_t h, py::ssize_t w) {
    if (layer.channels.size() == 1) return {h, w};
    return {h, w, py::ssize_t(layer.channels.size())};
}

// layers[name] as an AOV layer of `width` x `height`: uint32 ids, or float32 for the rest
// (any array-like that converts), in the shape layersFromImage gives it.
AovLayer aovFromArray(const std::string& name, py::handle value, uint32_t width, uint32_t height) {
    AovLayer layer;
    layer.name = name;
    layer.channels = aovChannels(name);
    const std::vector<py::ssize_t> shape = layerShape(layer, height, width);
    auto describe = [&] {
        std::string text = "(" + std::to_string(height) + ", " + std::to_string(width);
        if (shape.size() == 3) text += ", " + std::to_string(shape[2]);
        return text + ")";
    };
    auto check = [&](const py::array& a) {
        bool same = a.ndim() == py::ssize_t(shape.size());
        for (size_t d = 0; same && d < shape.size(); ++d) same = a.shape(py::ssize_t(d)) == shape[d];
        if (!same) throw py::value_error("layers[\"" + name + "\"] must be an array of shape " + describe());
    };
    if (aovHoldsIds(name)) {
        // Ids are exact integers: floats or negative numbers would be converted silently.
        py::array any = py::array::ensure(value);
        if (!any || any.dtype().kind() != 'u')
            throw py::value_error("layers[\"" + name + "\"] must be an unsigned integer array (uint32 ids)");
        auto ids = py::array_t<uint32_t, py::array::c_style | py::array::forcecast>::ensure(any);
        check(ids);
        layer.ids.assign(ids.data(), ids.data() + ids.size());
    } else {
        auto values = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(value);
        if (!values) throw py::value_error("layers[\"" + name + "\"] must be a float array of shape " + describe());
        check(values);
        layer.floats.assign(values.data(), values.data() + values.size());
    }
    return layer;
}

}  // namespace

py::object layersFromImage(Image&& image) {
    py::object layers = py::module_::import("penumbra").attr("Layers")();
    const py::ssize_t h = image.height, w = image.width;
    layers["rgb"] = ownedArray(std::move(image.rgb), {h, w, 3});
    for (AovLayer& layer : image.aovs) {
        const std::vector<py::ssize_t> shape = layerShape(layer, h, w);
        if (layer.ids.empty()) layers[py::str(layer.name)] = ownedArray(std::move(layer.floats), shape);
        else layers[py::str(layer.name)] = ownedIds(std::move(layer.ids), shape);
    }
    layers.attr("meta") = metaFromImage(image.meta);
    return layers;
}

py::array_t<float> falseColor(py::handle layers, const std::string& name) {
    Image image = imageFromLayers(layers);
    const py::ssize_t h = image.height, w = image.width;
    for (const AovLayer& layer : image.aovs)
        if (layer.name == name) return ownedArray(aovFalseColor(layer, size_t(h) * size_t(w)), {h, w, 3});
    throw py::key_error("no layer \"" + name + "\" (an AOV layer of these layers)");
}

Image imageFromLayers(py::handle layers) {
    if (!py::isinstance<py::dict>(layers)) throw py::type_error("layers must be a dict of arrays (as render returns)");
    py::dict dict = py::reinterpret_borrow<py::dict>(layers);
    for (auto item : dict) {
        const std::string name = py::str(item.first);
        if (name != "rgb" && aovChannels(name).empty())
            throw py::value_error("unknown layer \"" + name +
                                  "\" (known: rgb, albedo, normal, position, depth, shape_id, primitive_id, "
                                  "material_id, variance)");
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
    // The AOVs in the dict's order, which penumbra:aovs records (render() gives film.aovs').
    for (auto item : dict) {
        const std::string name = py::str(item.first);
        if (name != "rgb") image.aovs.push_back(aovFromArray(name, item.second, image.width, image.height));
    }
    image.meta = metaFromPython(py::getattr(layers, "meta", py::none()));
    return image;
}

}  // namespace penumbra::python
