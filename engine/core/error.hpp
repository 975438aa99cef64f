#pragma once
// Errors that reach the user. Thrown only at load and setup time (never in the frame loop);
// each carries the exit code of docs/cli.md ("Exit codes") so the CLI can report it.
#include <stdexcept>
#include <string>

namespace candela {

enum class ExitCode : int {
    ok = 0,
    internal = 1,   // a bug or an unexpected runtime failure
    bad_input = 2,  // a broken file, an unknown option, a value out of range
    no_gl = 3,      // no usable OpenGL 4.5 context
};

class Error : public std::runtime_error {
public:
    Error(ExitCode code, const std::string& message) : std::runtime_error(message), code_(code) {}
    ExitCode code() const { return code_; }

private:
    ExitCode code_;
};

// A problem with something the user gave us: "FILE: what is wrong".
inline Error bad_input(const std::string& message) { return Error(ExitCode::bad_input, message); }

}  // namespace candela
