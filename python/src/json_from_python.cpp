// Python -> JSON conversion (see json_from_python.h).
#include "json_from_python.h"

#include <cstdint>

#include "core/errors.h"
#include "scene/json_parse.h"
#include "scene/json_reader.h"

namespace py = pybind11;

namespace penumbra::python {
namespace {

nlohmann::json convert(py::handle value, const std::string& label, const std::string& path, size_t depth) {
    if (depth > kMaxJsonDepth) throwInputError(label, path, "nested deeper than 256 levels");
    // bool before int: True is an int in Python.
    if (value.is_none()) return nullptr;
    if (py::isinstance<py::bool_>(value)) return value.cast<bool>();
    if (py::isinstance<py::int_>(value)) {
        // As a JSON integer where one of 64 bits holds it, else as a double, as a file's
        // number text would parse.
        int overflow = 0;
        const long long v = PyLong_AsLongLongAndOverflow(value.ptr(), &overflow);
        if (overflow == 0) return int64_t(v);
        if (overflow > 0) {
            const unsigned long long u = PyLong_AsUnsignedLongLong(value.ptr());
            if (!PyErr_Occurred()) return uint64_t(u);
            PyErr_Clear();
        }
        return PyLong_AsDouble(value.ptr());  // +-inf beyond double range, as 1e999 in a file
    }
    if (py::isinstance<py::float_>(value)) return value.cast<double>();
    if (py::isinstance<py::str>(value)) return value.cast<std::string>();
    if (py::isinstance<py::dict>(value)) {
        nlohmann::json object = nlohmann::json::object();
        for (auto item : py::reinterpret_borrow<py::dict>(value)) {
            if (!py::isinstance<py::str>(item.first))
                throwInputError(label, path, "a key that is not a str (" + std::string(py::repr(item.first)) + ")");
            const std::string key = item.first.cast<std::string>();
            object[key] = convert(item.second, label, joinPath(path, key), depth + 1);
        }
        return object;
    }
    if (py::isinstance<py::list>(value) || py::isinstance<py::tuple>(value)) {
        nlohmann::json array = nlohmann::json::array();
        size_t i = 0;
        for (py::handle element : value) array.push_back(convert(element, label, indexPath(path, i++), depth + 1));
        return array;
    }
    // numpy arrays and scalars (and anything else that lists itself as plain values).
    if (py::hasattr(value, "tolist") && !py::isinstance<py::str>(value)) {
        py::object plain = value.attr("tolist")();
        if (!plain.is(value)) return convert(plain, label, path, depth + 1);
    }
    throwInputError(label, path,
                    "a Python " + std::string(py::str(value.get_type().attr("__name__"))) + " is not a JSON value");
}

}  // namespace

nlohmann::json jsonFromPython(py::handle value, const std::string& label, const std::string& path) {
    return convert(value, label, path, 0);
}

}  // namespace penumbra::python
