// The extension module penumbra._penumbra: the functions and classes python/penumbra
// re-exports (docs/guide/python.md, docs/SCENE_FORMAT.md "Python"). Errors: InputError (bad
// input, exit status 2 on the command line) becomes SceneError, any other failure
// RenderError, each with the command line's one-line message.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>
#include <vulkan/vulkan.h>

#include "core/errors.h"
#include "gpu/context.h"
#include "image/tone_map.h"
#include "interruptible.h"
#include "json_from_python.h"
#include "layers.h"
#include "scene_renderer.h"

namespace py = pybind11;

namespace penumbra::python {
namespace {

// Python's label for a scene given as a dict, where a file's name would stand in messages.
constexpr const char* kDictLabel = "<dict>";

// The scene argument: a path (str or os.PathLike) read as the command line reads it, or a
// dict (the same JSON) whose relative file names resolve against the working directory.
SceneDocument sceneDocument(py::handle scene) {
    if (py::isinstance<py::dict>(scene)) {
        SceneDocument document;
        document.label = kDictLabel;
        document.baseDir = std::filesystem::current_path();
        document.name = "scene";
        document.doc = jsonFromPython(scene, kDictLabel);
        return document;
    }
    py::object fspath = py::module_::import("os").attr("fspath");
    std::filesystem::path file;
    try {
        file = fspath(scene).cast<std::string>();
    } catch (const py::error_already_set&) {
        throw py::type_error("scene must be a path or a dict, not " +
                             std::string(py::str(scene.get_type().attr("__name__"))));
    }
    return readSceneDocument(file);
}

// set= and the shorthands, in the command line's order: every `set` entry, then spp,
// seed, width, height, aovs (host/main.cpp, collectOverrides).
std::vector<JsonOverride> overridesOf(const py::object& set, const py::object& spp, const py::object& seed,
                                      const py::object& width, const py::object& height, const py::object& aovs) {
    std::vector<JsonOverride> overrides;
    auto add = [&](const std::string& path, py::handle value) {
        Override o{path, ""};
        nlohmann::json json = jsonFromPython(value, "--set " + path);
        o.value = json.dump();
        // The path's syntax, as --set checks it (and no '=', where --set would split).
        if (parseOverride(o.path + "=" + o.value).path != o.path)
            throw InputError("--set " + path + ": '=' in the path (expected a path like lights[0].power)");
        overrides.push_back({std::move(o), std::move(json)});
    };
    if (!set.is_none()) {
        if (!py::isinstance<py::dict>(set)) throw py::type_error("set must be a dict {\"path\": value}");
        for (auto item : py::reinterpret_borrow<py::dict>(set)) {
            if (!py::isinstance<py::str>(item.first)) throw py::type_error("set's keys must be str paths");
            add(item.first.cast<std::string>(), item.second);
        }
    }
    if (!spp.is_none()) add("sampler.spp", spp);
    if (!seed.is_none()) add("sampler.seed", seed);
    if (!width.is_none()) add("film.width", width);
    if (!height.is_none()) add("film.height", height);
    // aovs= is --aov's list: film.aovs, its names checked where the scene loads (the CLI's
    // message). A bare string would be one name per character; refused as a type.
    if (!aovs.is_none()) {
        if (!py::isinstance<py::list>(aovs) && !py::isinstance<py::tuple>(aovs))
            throw py::type_error("aovs must be a list of layer names, e.g. [\"depth\", \"normal\"]");
        add("film.aovs", py::list(aovs));
    }
    return overrides;
}

int deviceIndexOf(const py::object& device) {
    if (device.is_none()) return -1;  // PENUMBRA_DEVICE or the automatic choice
    const int index = device.cast<int>();
    if (index < 0) throw py::value_error("device must be an index of penumbra.devices() (>= 0) or None");
    return index;
}

SceneRenderer* makeRenderer(const py::object& scene, const py::object& spp, const py::object& seed,
                            const py::object& width, const py::object& height, const py::object& set,
                            const py::object& aovs, const py::object& device) {
    SceneDocument document = sceneDocument(scene);
    std::vector<JsonOverride> overrides = overridesOf(set, spp, seed, width, height, aovs);
    const int index = deviceIndexOf(device);
    return runInterruptible(
        [&](const std::atomic<bool>&) { return new SceneRenderer(std::move(document), std::move(overrides), index); });
}

py::object renderWith(SceneRenderer& renderer, const py::object& spp, const py::object& seed, const py::object& width,
                      const py::object& height, const py::object& set, const py::object& aovs) {
    std::vector<JsonOverride> overrides = overridesOf(set, spp, seed, width, height, aovs);
    Image image = runInterruptible([&](const std::atomic<bool>& cancel) { return renderer.render(overrides, cancel); });
    return layersFromImage(std::move(image));
}

py::list devices() {
    int chosen = -1;
    std::vector<gpu::DeviceInfo> list;
    {
        py::gil_scoped_release release;
        list = gpu::Context::listDevices(&chosen);
    }
    py::list out;
    for (const gpu::DeviceInfo& d : list) {
        py::dict entry;
        entry["index"] = d.index;
        entry["name"] = d.name;
        entry["type"] = d.type;
        entry["vulkan"] = std::to_string(VK_API_VERSION_MAJOR(d.apiVersion)) + "." +
                          std::to_string(VK_API_VERSION_MINOR(d.apiVersion));
        entry["compute"] = d.hasCompute;
        entry["driver"] = d.driverName;
        entry["driver_info"] = d.driverInfo;
        entry["chosen"] = int(d.index) == chosen;
        out.append(entry);
    }
    return out;
}

}  // namespace
}  // namespace penumbra::python

PYBIND11_MODULE(_penumbra, m) {
    using namespace penumbra;
    using namespace penumbra::python;
    m.doc() = "Penumbra's renderer for scripts (docs/guide/python.md)";

    // Kept for the life of the process, as the module itself is.
    static PyObject* sceneError = PyErr_NewException("penumbra.SceneError", PyExc_ValueError, nullptr);
    static PyObject* renderError = PyErr_NewException("penumbra.RenderError", PyExc_RuntimeError, nullptr);
    m.add_object("SceneError", py::handle(sceneError));
    m.add_object("RenderError", py::handle(renderError));
    // pybind11's translator type takes the exception_ptr by value.
    py::register_exception_translator([](std::exception_ptr p) {  // NOLINT(performance-unnecessary-value-param)
        try {
            if (p) std::rethrow_exception(p);
        } catch (const py::error_already_set&) {
            throw;  // a Python exception (KeyboardInterrupt): pybind11's own translator
        } catch (const py::builtin_exception&) {
            throw;  // TypeError, ValueError of the arguments
        } catch (const InputError& e) {
            PyErr_SetString(sceneError, e.what());
        } catch (const std::exception& e) {
            PyErr_SetString(renderError, e.what());
        }
    });

    const auto scene = py::arg("scene");
    py::class_<SceneRenderer>(m, "Renderer",
                              "Keeps the device, the uploaded scene and the compiled kernels across renders.")
        .def(py::init(&makeRenderer), scene, py::kw_only(), py::arg("spp") = py::none(), py::arg("seed") = py::none(),
             py::arg("width") = py::none(), py::arg("height") = py::none(), py::arg("set") = py::none(),
             py::arg("aovs") = py::none(), py::arg("device") = py::none())
        .def("render", &renderWith, py::kw_only(), py::arg("spp") = py::none(), py::arg("seed") = py::none(),
             py::arg("width") = py::none(), py::arg("height") = py::none(), py::arg("set") = py::none(),
             py::arg("aovs") = py::none(), "Renders with these overrides on top of the constructor's; returns Layers.")
        // The counts wait for a render under way (SceneRenderer's mutex): without the GIL,
        // so that other Python threads run meanwhile. (A lambda: pybind11 >= 2.11 refuses
        // call_guard on properties.)
        .def_property_readonly(
            "kernel_compilations",
            [](const SceneRenderer& r) {
                py::gil_scoped_release release;
                return r.kernelCompilations();
            },
            "Kernels compiled so far (driver compilations; the first render makes one).")
        .def_property_readonly(
            "scene_uploads",
            [](const SceneRenderer& r) {
                py::gil_scoped_release release;
                return r.sceneUploads();
            },
            "Times the scene was uploaded to the device (the constructor's included).")
        .def_property_readonly("device", &SceneRenderer::deviceName, "The Vulkan device's name.");

    m.def(
        "write_exr",
        [](const std::filesystem::path& path, const py::handle& layers) {
            Image image = imageFromLayers(layers);
            py::gil_scoped_release release;
            writeExr(path, image);
        },
        py::arg("path"), py::arg("layers"), "Writes layers (and layers.meta) as penumbra render writes its EXR.");
    m.def(
        "write_png",
        [](const std::filesystem::path& path, const py::handle& layers, float exposure, const std::string& tonemap) {
            ToneLook look;
            look.exposure = exposure;
            const std::optional<ToneCurve> curve = toneCurveFromName(tonemap);
            if (!curve) throw InputError("tonemap: '" + tonemap + "' is not a tone curve (clamp, filmic)");
            look.curve = *curve;
            Image image = imageFromLayers(layers);
            py::gil_scoped_release release;
            writePng(path, image, look);
        },
        py::arg("path"), py::arg("layers"), py::arg("exposure") = 0.0f, py::arg("tonemap") = "clamp",
        "Writes layers[\"rgb\"] as the 8-bit sRGB PNG of penumbra render --png --exposure --tonemap.");
    m.def(
        "read_exr",
        [](const std::filesystem::path& path) {
            Image image;
            {
                py::gil_scoped_release release;
                image = readExr(path);
            }
            return layersFromImage(std::move(image));
        },
        py::arg("path"), "Reads an EXR into Layers, with its header attributes in .meta.");
    m.def("false_color", &falseColor, py::arg("layers"), py::arg("name"),
          "layers[name] (an AOV) as the preview shows it: linear float32 (H, W, 3) for write_png.");
    m.def("devices", &devices, "The Vulkan devices, as penumbra devices lists them.");
}
