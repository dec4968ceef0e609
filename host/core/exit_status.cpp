// Failure -> one line and an exit status (see exit_status.h).
#include "core/exit_status.h"

#include <cstdio>
#include <exception>

#include "core/errors.h"

namespace penumbra {

void printErrorLine(const char* program, const std::string& message) {
    std::string line = message;
    for (char& c : line)
        if (c == '\n' || c == '\r') c = ' ';
    std::fprintf(stderr, "%s: %s\n", program, line.c_str());
}

int runReportingErrors(const char* program, const std::function<int()>& body) {
    try {
        return body();
    } catch (const InputError& e) {
        printErrorLine(program, e.what());
        return 2;
    } catch (const std::exception& e) {
        printErrorLine(program, e.what());
        return 1;
    }
}

}  // namespace penumbra
