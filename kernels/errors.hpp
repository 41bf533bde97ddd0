// Error types of meshless. Conventions (DESIGN.md): assert for programmer errors; these exceptions
// for bad data and environment. The CLI is the only place that catches them and maps them to exit
// codes: UsageError -> 1, FormatError/IoError -> 2, anything else -> 3.
// Messages are one line and name the file (when there is one) and what was expected.
#pragma once
#include <stdexcept>
#include <string>

namespace meshless {

/// Malformed, truncated or unsupported input data (wrong magic, version, sizes, values).
struct FormatError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

/// The environment failed us: a file cannot be opened, read, written or renamed.
struct IoError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

/// The user asked for something inconsistent (bad flag, missing argument).
struct UsageError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

/// A downstream pipe closed (EPIPE): not an error for the user, the CLI exits quietly.
struct BrokenPipe : std::runtime_error {
    BrokenPipe() : std::runtime_error("broken pipe") {}
};

}  // namespace meshless
