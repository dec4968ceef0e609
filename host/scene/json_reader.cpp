// JsonReader: type, range and unknown-key checks with JSON-path error messages.
// Which keys exist and what they mean is decided by the loaders that use it.
#include "scene/json_reader.h"

#include <algorithm>
#include <atomic>
#include <cfloat>
#include <cmath>

#include "core/errors.h"

namespace penumbra {

std::string joinPath(const std::string& path, const std::string& key) {
    return path.empty() ? key : path + "." + key;
}

std::string indexPath(const std::string& path, size_t index) {
    return path + "[" + std::to_string(index) + "]";
}

namespace {
std::atomic<size_t> g_pathTexts{0};
}  // namespace

size_t jsonPathTextCount() { return g_pathTexts; }

std::string JsonReader::path() const {
    ++g_pathTexts;
    std::vector<const Step*> steps;
    for (const Step* s = m_step.get(); s; s = s->parent.get()) steps.push_back(s);
    std::string result;
    for (auto s = steps.rbegin(); s != steps.rend(); ++s)
        result = (*s)->isIndex ? indexPath(result, (*s)->index) : joinPath(result, (*s)->key);
    return result;
}

void JsonReader::fail(const std::string& message) const { throwInputError(*m_file, path(), message); }

std::string JsonReader::typeName() const {
    switch (m_value->type()) {
        case nlohmann::json::value_t::null: return "null";
        case nlohmann::json::value_t::object: return "an object";
        case nlohmann::json::value_t::array: return "an array";
        case nlohmann::json::value_t::string: return "a string";
        case nlohmann::json::value_t::boolean: return "a boolean";
        case nlohmann::json::value_t::binary: return "binary data";
        default: return "a number";
    }
}

void JsonReader::failType(const char* expected) const {
    fail(std::string("expected ") + expected + ", got " + typeName());
}

void JsonReader::expectKeys(std::initializer_list<const char*> allowed, const std::string& what) const {
    expectKeys(std::span<const char* const>(allowed.begin(), allowed.size()), what);
}

void JsonReader::expectKeys(std::span<const char* const> allowed, const std::string& what) const {
    if (!m_value->is_object()) failType("an object");
    for (const auto& item : m_value->items()) {
        const std::string& key = item.key();
        if (std::any_of(allowed.begin(), allowed.end(), [&](const char* a) { return key == a; })) continue;
        std::string list;
        for (const char* a : allowed) list += (list.empty() ? "" : ", ") + std::string(a);
        fail("unknown key \"" + key + "\" (" + what + " allows: " + list + ")");
    }
}

bool JsonReader::has(const char* key) const {
    if (!m_value->is_object()) failType("an object");
    return m_value->contains(key);
}

JsonReader JsonReader::at(const char* key) const {
    if (!has(key)) fail(std::string("missing required field \"") + key + "\"");
    return JsonReader(m_value->at(key), *this, Step{m_step, key, 0, false});
}

std::optional<JsonReader> JsonReader::find(const char* key) const {
    if (!has(key)) return std::nullopt;
    return at(key);
}

std::vector<std::string> JsonReader::keys() const {
    if (!m_value->is_object()) failType("an object");
    std::vector<std::string> result;
    for (const auto& item : m_value->items()) result.push_back(item.key());
    return result;
}

size_t JsonReader::size() const {
    if (!m_value->is_array()) failType("an array");
    return m_value->size();
}

JsonReader JsonReader::operator[](size_t index) const {
    if (index >= size()) fail("index " + std::to_string(index) + " out of range");
    return JsonReader((*m_value)[index], *this, Step{m_step, {}, index, true});
}

float JsonReader::number() const {
    if (!m_value->is_number()) failType("a number");
    double x = m_value->get<double>();
    // Finite as a float: positions, colours and distances all end up as 32-bit floats.
    if (!std::isfinite(x) || std::fabs(x) > double(FLT_MAX)) fail("number is not finite (or too large for a float)");
    return static_cast<float>(x);
}

int64_t JsonReader::integer(int64_t lo, int64_t hi) const {
    if (!m_value->is_number()) failType("an integer");
    int64_t value = 0;
    if (m_value->is_number_unsigned()) {
        uint64_t u = m_value->get<uint64_t>();
        value = u > uint64_t(INT64_MAX) ? INT64_MAX : int64_t(u);
    } else if (m_value->is_number_integer()) {
        value = m_value->get<int64_t>();
    } else {
        double x = m_value->get<double>();
        if (!std::isfinite(x) || x != std::floor(x)) failType("an integer");
        value = std::fabs(x) > 9e18 ? (x > 0 ? INT64_MAX : INT64_MIN) : int64_t(x);
    }
    if (value < lo || value > hi)
        fail("must be an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got " +
             m_value->dump());
    return value;
}

bool JsonReader::boolean() const {
    if (!m_value->is_boolean()) failType("true or false");
    return m_value->get<bool>();
}

std::string JsonReader::string() const {
    if (!m_value->is_string()) failType("a string");
    return m_value->get<std::string>();
}

std::string JsonReader::choice(std::initializer_list<const char*> choices) const {
    return choice(std::span<const char* const>(choices.begin(), choices.size()));
}

std::string JsonReader::choice(std::span<const char* const> choices) const {
    std::string value = string();
    std::string list;
    for (const char* c : choices) {
        if (value == c) return value;
        list += (list.empty() ? "\"" : ", \"") + std::string(c) + "\"";
    }
    fail("\"" + value + "\" is not one of " + list);
}

glm::vec3 JsonReader::vec3() const {
    if (!m_value->is_array() || m_value->size() != 3) failType("an array of 3 numbers");
    std::vector<float> v = numbers();  // element readers (and their paths) only on an error
    return {v[0], v[1], v[2]};
}

glm::vec3 JsonReader::color() const {
    glm::vec3 c;
    if (m_value->is_number()) {
        c = glm::vec3(number());
    } else {
        if (!m_value->is_array() || m_value->size() != 3) failType("an RGB triple [r,g,b] or a number");
        c = vec3();
    }
    if (c.x < 0.0f || c.y < 0.0f || c.z < 0.0f) fail("must not be negative, got " + m_value->dump());
    return c;
}

std::vector<float> JsonReader::numbers() const {
    std::vector<float> result(size());
    for (size_t i = 0; i < result.size(); ++i) {
        // Fast path without building a JSON path per element; the slow path reports errors.
        const nlohmann::json& v = (*m_value)[i];
        double x = v.is_number() ? v.get<double>() : NAN;
        result[i] = std::isfinite(x) && std::fabs(x) <= double(FLT_MAX) ? float(x) : (*this)[i].number();
    }
    return result;
}

}  // namespace penumbra
