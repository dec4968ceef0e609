// Input scripts: timed events that drive the preview without a user (tests, demos).
// One event per line, '#' starts a comment, blank lines are ignored; frames count from 1
// and an event for frame N is applied before frame N renders:
//   frame N key K               press key K: 1 2 3 4 h s + - p r q esc
//   frame N drag DX DY [BUTTON] drag by DX, DY window pixels (y down); BUTTON left
//                               (default: orbit), right or middle (pan)
//   frame N scroll STEPS        turn the wheel (positive: zoom in)
//   frame N resize W H          resize the window to W x H
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "preview/input.h"

namespace penumbra::preview {

struct ScriptEvent {
    uint32_t frame = 1;
    InputEvent event;
};

// Parses script text; `name` labels errors. Throws InputError("NAME:LINE: why").
// The events come back ordered by frame (stable for events of the same frame).
std::vector<ScriptEvent> parseInputScript(const std::string& text, const std::string& name);
// Scripts are small: 16 MiB at most (hundreds of thousands of events).
inline constexpr uint64_t kMaxScriptBytes = uint64_t(1) << 24;
// Reads and parses a script file; a missing, non-regular or larger file is an InputError
// naming it (core/input_file.h).
std::vector<ScriptEvent> loadInputScript(const std::filesystem::path& file);

}  // namespace penumbra::preview
