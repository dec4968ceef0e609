// The exit statuses of SCENE_FORMAT.md for every program of the project: runs the body,
// prints a failure as one line "PROGRAM: message" on stderr, and returns 2 for bad input
// (InputError) or 1 for anything else.
#pragma once

#include <exception>
#include <functional>
#include <string>

namespace penumbra {

// One line on stderr, newlines in the message turned into spaces.
void printErrorLine(const char* program, const std::string& message);

// The message for a failure: e.what(), except that running out of host memory
// (std::bad_alloc) says so in words.
std::string failureMessage(const std::exception& e);

int runReportingErrors(const char* program, const std::function<int()>& body);

}  // namespace penumbra
