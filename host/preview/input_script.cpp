// Parsing of preview input scripts (format in input_script.h).
#include "preview/input_script.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "core/errors.h"
#include "core/input_file.h"

namespace penumbra::preview {
namespace {

[[noreturn]] void fail(const std::string& name, int line, const std::string& why) {
    throw InputError(name + ":" + std::to_string(line) + ": " + why);
}

double number(std::istringstream& in, const std::string& what, const std::string& name, int line) {
    std::string word;
    if (!(in >> word)) fail(name, line, "missing " + what);
    try {
        size_t used = 0;
        double value = std::stod(word, &used);
        if (used != word.size() || !std::isfinite(value)) throw std::invalid_argument(word);
        return value;
    } catch (const std::exception&) {
        fail(name, line, what + " is not a finite number: " + elide(word));
    }
}

}  // namespace

std::vector<ScriptEvent> parseInputScript(const std::string& text, const std::string& name) {
    std::vector<ScriptEvent> events;
    std::istringstream lines(text);
    std::string raw;
    for (int lineNumber = 1; std::getline(lines, raw); ++lineNumber) {
        if (size_t hash = raw.find('#'); hash != std::string::npos) raw.resize(hash);
        std::istringstream in(raw);
        std::string word;
        if (!(in >> word)) continue;
        if (word != "frame") fail(name, lineNumber, "expected 'frame N ...', found '" + elide(word) + "'");
        double frame = number(in, "frame number", name, lineNumber);
        if (frame < 1 || frame != std::floor(frame) || frame > 1e9)
            fail(name, lineNumber, "frame numbers are whole numbers from 1");
        ScriptEvent event;
        event.frame = uint32_t(frame);
        std::string verb;
        if (!(in >> verb)) fail(name, lineNumber, "missing event after the frame number");
        if (verb == "key") {
            std::string key;
            if (!(in >> key)) fail(name, lineNumber, "missing key name");
            auto action = actionForKeyName(key);
            if (!action) fail(name, lineNumber, "unknown key '" + elide(key) + "' (keys: 1 2 3 4 h s + - p r q esc)");
            event.event = InputEvent::key(*action);
        } else if (verb == "drag") {
            double dx = number(in, "drag dx", name, lineNumber);
            double dy = number(in, "drag dy", name, lineNumber);
            MouseButton button = MouseButton::Left;
            if (std::string which; in >> which) {
                if (which == "left") button = MouseButton::Left;
                else if (which == "right") button = MouseButton::Right;
                else if (which == "middle") button = MouseButton::Middle;
                else fail(name, lineNumber, "unknown mouse button '" + elide(which) + "' (left, right or middle)");
            }
            event.event = InputEvent::drag(button, dx, dy);
        } else if (verb == "scroll") {
            event.event = InputEvent::scroll(number(in, "scroll steps", name, lineNumber));
        } else if (verb == "resize") {
            double w = number(in, "width", name, lineNumber), h = number(in, "height", name, lineNumber);
            if (w < 1 || h < 1 || w > 16384 || h > 16384 || w != std::floor(w) || h != std::floor(h))
                fail(name, lineNumber, "window size must be whole numbers in 1..16384");
            event.event = InputEvent::resize(int(w), int(h));
        } else {
            fail(name, lineNumber, "unknown event '" + elide(verb) + "' (key, drag, scroll or resize)");
        }
        if (std::string extra; in >> extra)
            fail(name, lineNumber, "unexpected '" + elide(extra) + "' at the end of the line");
        events.push_back(event);
    }
    std::stable_sort(events.begin(), events.end(),
                     [](const ScriptEvent& a, const ScriptEvent& b) { return a.frame < b.frame; });
    return events;
}

std::vector<ScriptEvent> loadInputScript(const std::filesystem::path& file) {
    // Under the input-file rules: a regular file of at most kMaxScriptBytes.
    return parseInputScript(readInputFile(file, file.string(), kMaxScriptBytes), file.string());
}

}  // namespace penumbra::preview
