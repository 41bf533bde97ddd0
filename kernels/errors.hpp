// Error types of the meshless libraries (kernels/, formats/, ooc/, stream/). Conventions (docs/architecture.md):
// assert for programmer errors; these exceptions for bad arguments, bad data and a failing environment.
// Messages are one line and name the file (when there is one) and what was expected.
// Only cli/ catches them and maps them to exit codes (cli/errors.hpp, the one mapping): InvalidArgument
// -> 1 (like the CLI's own UsageError), FormatError/IoError -> 2, BrokenPipe -> 0 (quiet), others -> 3.
#pragma once
#include <stdexcept>
#include <string>

namespace meshless {

/// Malformed, truncated or unsupported input data (wrong magic, version, sizes, values). The message
/// names the file and, where known, the byte offset or the field.
struct FormatError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

/// The environment failed us: a file cannot be opened, read, written or renamed.
struct IoError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

/// A caller passed a parameter outside the documented domain of a library function (a NaN isovalue,
/// a brick edge of 1, a memory budget smaller than one brick, fewer than 4 points for a field, an
/// output path a writer cannot use). The message names the parameter (and the file, when there is
/// one) and the accepted range. Parameters usually come from the user's command line, so the CLI
/// reports it like a usage error; it is not the CLI's UsageError (cli/errors.hpp), which the
/// libraries never throw.
struct InvalidArgument : std::invalid_argument {
    using std::invalid_argument::invalid_argument;
};

/// A downstream pipe closed (EPIPE): not an error for the user, the CLI exits quietly.
struct BrokenPipe : std::runtime_error {
    BrokenPipe() : std::runtime_error("broken pipe") {}
};

/// fn(), its FormatError and IoError rethrown (same type) with `prefix` before the message, unless
/// the message already begins with `owner` + ":" (a file that names other files: a detached header
/// names its data file's errors, "quarter.nhdr: data file ./quarter.1: cannot open").
template <class Fn>
decltype(auto) with_error_prefix(const std::string& owner, const std::string& prefix, Fn&& fn) {
    const auto named = [&](const char* what) { return std::string(what).rfind(owner + ":", 0) == 0; };
    try {
        return fn();
    } catch (const FormatError& e) {
        if (named(e.what())) throw;
        throw FormatError(prefix + e.what());
    } catch (const IoError& e) {
        if (named(e.what())) throw;
        throw IoError(prefix + e.what());
    }
}

}  // namespace meshless
