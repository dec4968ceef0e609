// Failure -> one line and an exit status (see exit_status.h).
#include "core/exit_status.h"

#include <cstdio>
#include <exception>
#include <new>

#include "core/errors.h"

namespace penumbra {

void printErrorLine(const char* program, const std::string& message) {
    std::string line = message;
    for (char& c : line)
        if (c == '\n' || c == '\r') c = ' ';
    std::fprintf(stderr, "%s: %s\n", program, line.c_str());
}

std::string failureMessage(const std::exception& e) {
    // What ran out, not "std::bad_alloc". Device memory has its own message (gpu/vk_check).
    if (dynamic_cast<const std::bad_alloc*>(&e))
        return "out of memory: the host could not allocate what this run needs (a smaller film, scene or image "
               "may fit)";
    return e.what();
}

int runReportingErrors(const char* program, const std::function<int()>& body) {
    try {
        return body();
    } catch (const InputError& e) {
        printErrorLine(program, e.what());
        return 2;
    } catch (const std::exception& e) {
        printErrorLine(program, failureMessage(e));
        return 1;
    }
}

}  // namespace penumbra
