// A small typed view of one value in a parsed JSON document that knows its JSON path
// (e.g. `shapes[3].material`) and file name, so every validation error is one line naming
// both. It checks types, ranges and unknown keys; what the values mean is load_json.cpp's.
#pragma once

#include <cstdint>
#include <initializer_list>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

namespace penumbra {

class JsonReader {
public:
    // A reader of the document's root.
    JsonReader(const nlohmann::json& value, std::string file)
        : m_value(&value), m_file(std::make_shared<const std::string>(std::move(file))) {}

    const nlohmann::json& json() const { return *m_value; }
    const std::string& file() const { return *m_file; }
    // The JSON path as text, e.g. "shapes[3].material". Readers keep only a link to their
    // parent's step (one small node each), and the text is built here, for a message, so
    // that reading a million-element array stays linear and cheap.
    std::string path() const;

    // Throws InputError("<file>: <path>: <message>").
    [[noreturn]] void fail(const std::string& message) const;

    // --- objects -------------------------------------------------------------------
    // Fails unless this is an object whose keys are all in `allowed`; `what` names the
    // object in the message (e.g. "sphere"), which lists the allowed keys.
    void expectKeys(std::initializer_list<const char*> allowed, const std::string& what = "object") const;
    void expectKeys(std::span<const char* const> allowed, const std::string& what = "object") const;
    bool has(const char* key) const;
    JsonReader at(const char* key) const;                // required member
    std::optional<JsonReader> find(const char* key) const;  // optional member
    std::vector<std::string> keys() const;               // object keys, sorted

    // --- arrays ----------------------------------------------------------------------
    size_t size() const;  // fails unless this is an array
    JsonReader operator[](size_t index) const;

    // --- scalars -------------------------------------------------------------------------
    // A number that is finite as a 32-bit float (nlohmann reads the literal 1e999 as +inf,
    // and 1e300 is finite only as a double: both are rejected here).
    float number() const;
    // An integer in [lo, hi]; a float with an integral value (e.g. 512.0) is accepted.
    int64_t integer(int64_t lo, int64_t hi) const;
    uint32_t uint32() const { return static_cast<uint32_t>(integer(0, UINT32_MAX)); }
    bool boolean() const;
    std::string string() const;
    // One of `choices`; the message lists them.
    std::string choice(std::initializer_list<const char*> choices) const;
    std::string choice(std::span<const char* const> choices) const;

    // --- vectors ---------------------------------------------------------------------------
    glm::vec3 vec3() const;  // an array of exactly 3 numbers
    // A non-negative RGB triple. Leniency beyond SCENE_FORMAT.md: a single number means
    // grey ([x,x,x]), so `"power": 100` is a white 100 W light.
    glm::vec3 color() const;
    std::vector<float> numbers() const;  // an array of numbers (any length)

    // Optional members with defaults.
    float numberOr(const char* key, float fallback) const { return has(key) ? at(key).number() : fallback; }
    glm::vec3 vec3Or(const char* key, glm::vec3 fallback) const { return has(key) ? at(key).vec3() : fallback; }
    glm::vec3 colorOr(const char* key, glm::vec3 fallback) const { return has(key) ? at(key).color() : fallback; }

private:
    // One step from the root: a key or an index, and the steps before it.
    struct Step {
        std::shared_ptr<const Step> parent;
        std::string key;
        size_t index;
        bool isIndex;
    };

    JsonReader(const nlohmann::json& value, const JsonReader& parent, Step step)
        : m_value(&value), m_file(parent.m_file), m_step(std::make_shared<const Step>(std::move(step))) {}
    std::string typeName() const;
    [[noreturn]] void failType(const char* expected) const;

    const nlohmann::json* m_value;
    std::shared_ptr<const std::string> m_file;
    std::shared_ptr<const Step> m_step;  // null at the root
};

// How many times a JSON path has been turned into text in this process (a test hook:
// loading a valid scene must build none).
size_t jsonPathTextCount();

// "a.b" / "a[3]" path building, shared with the glTF loader's messages.
std::string joinPath(const std::string& path, const std::string& key);
std::string indexPath(const std::string& path, size_t index);

}  // namespace penumbra
