// The shared JSON parser: a byte scan for the nesting depth, then nlohmann's SAX parser
// with a document builder of our own that refuses duplicate keys and knows the JSON path
// of the value being read. nlohmann's callback parser is not used: it rescans the parent
// container after every object, which made arrays of objects parse in O(n^2).
#include "scene/json_parse.h"

#include <algorithm>
#include <vector>

#include "core/errors.h"
#include "scene/json_reader.h"

namespace penumbra {
namespace {

using nlohmann::json;

// nlohmann's messages end "...; last read: '<text>'" (optionally followed by "; expected
// ..."): drop the echo, since the text may be any file (an input must never be echoed).
std::string withoutEcho(std::string message) {
    size_t start = message.find("; last read: '");
    if (start == std::string::npos) return message;
    size_t end = message.find("'; expected ", start);
    message.erase(start, end == std::string::npos ? std::string::npos : end + 1 - start);
    return message;
}

class DocumentBuilder {
public:
    explicit DocumentBuilder(const std::string& label) : m_label(label) {}

    json& root() { return m_root; }

    bool null() { return put(nullptr); }
    bool boolean(bool v) { return put(v); }
    bool number_integer(json::number_integer_t v) { return put(v); }
    bool number_unsigned(json::number_unsigned_t v) { return put(v); }
    bool number_float(json::number_float_t v, const json::string_t&) { return put(v); }
    bool string(json::string_t& v) { return put(std::move(v)); }
    bool binary(json::binary_t& v) { return put(json::binary(std::move(v))); }

    bool start_object(size_t) { return open(json::object(), false); }
    bool start_array(size_t) { return open(json::array(), true); }
    bool end_object() { return close(); }
    bool end_array() { return close(); }

    bool key(json::string_t& k) {
        Frame& f = m_frames.back();
        // Objects are ordered maps: the lookup is O(log n), the whole parse stays linear.
        if (f.value->contains(k)) throwInputError(m_label, path(false), "duplicate key \"" + k + "\"");
        f.key = k;
        f.slot = &(*f.value)[k];
        return true;
    }

    bool parse_error(size_t byte, const std::string&, const nlohmann::detail::exception& e) {
        std::string what = e.what();
        if (e.id == 406) {
            // A number literal beyond double range (1e999): name the value's path.
            size_t at = what.find("] ");
            throwInputError(m_label, path(true),
                            "number is not finite (" + what.substr(at == std::string::npos ? 0 : at + 2) + ")");
        }
        // "[json.exception.parse_error.101] parse error at line 3, column 5: syntax error ..."
        size_t at = what.find("line ");
        std::string detail = at != std::string::npos ? what.substr(at) : "byte " + std::to_string(byte) + ": " + what;
        std::replace(detail.begin(), detail.end(), '\n', ' ');
        throwInputError(m_label, "", withoutEcho(detail));
    }

private:
    struct Frame {
        json* value;  // the array or object being filled
        bool isArray;
        std::string key;       // objects: the key of the member being read
        json* slot = nullptr;  // objects: where that member goes
    };

    json* place(json&& value) {
        if (m_frames.empty()) {
            m_root = std::move(value);
            return &m_root;
        }
        Frame& f = m_frames.back();
        if (f.isArray) {
            f.value->push_back(std::move(value));
            return &f.value->back();
        }
        *f.slot = std::move(value);
        return f.slot;
    }
    bool put(json&& value) {
        place(std::move(value));
        return true;
    }
    bool open(json&& empty, bool isArray) {
        json* container = place(std::move(empty));
        m_frames.push_back({container, isArray, {}, nullptr});
        return true;
    }
    bool close() {
        m_frames.pop_back();
        return true;
    }

    // The JSON path, built only for a message. `pending`: of the value being read now
    // (its index is the array's size, its key the last key); else of the innermost container.
    std::string path(bool pending) const {
        std::string result;
        for (size_t i = 0; i < m_frames.size(); ++i) {
            const Frame& f = m_frames[i];
            bool innermost = i + 1 == m_frames.size();
            if (innermost && !pending) break;
            if (f.isArray) result = indexPath(result, innermost ? f.value->size() : f.value->size() - 1);
            else result = joinPath(result, f.key);
        }
        return result;
    }

    const std::string& m_label;
    json m_root;
    std::vector<Frame> m_frames;
};

}  // namespace

void checkJsonDepth(std::string_view text, const std::string& label) {
    size_t depth = 0, line = 1, column = 0;
    bool inString = false, escaped = false;
    for (char c : text) {
        ++column;
        if (c == '\n') {
            ++line;
            column = 0;
        }
        if (inString) {
            if (escaped) escaped = false;
            else if (c == '\\') escaped = true;
            else if (c == '"') inString = false;
        } else if (c == '"') {
            inString = true;
        } else if (c == '[' || c == '{') {
            if (++depth > kMaxJsonDepth)
                throwInputError(label, "",
                                "line " + std::to_string(line) + ", column " + std::to_string(column) +
                                    ": nested deeper than " + std::to_string(kMaxJsonDepth) + " levels");
        } else if ((c == ']' || c == '}') && depth > 0) {
            --depth;
        }
    }
}

json parseJsonText(std::string_view text, const std::string& label) {
    checkJsonDepth(text, label);
    DocumentBuilder builder(label);
    json::sax_parse(text.begin(), text.end(), &builder);
    return std::move(builder.root());
}

}  // namespace penumbra
