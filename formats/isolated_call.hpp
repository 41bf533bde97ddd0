// A call run in a child process of its own (fork), for third-party decoders that abort or crash on
// damaged input (GDCM's RLE and JPEG decoders assert): their failure ends the child, and the caller
// gets a result to turn into one line naming the file. The child writes its output into memory
// shared with this process (an anonymous MAP_SHARED mapping of `bytes`), which is copied to `out`
// only when the child exits 0; the child's own exceptions come back as their what() text. The child
// resets the signals this process catches (formats/temporary_files.hpp: its handlers would remove
// this process's temporaries) and is killed when this process dies or the deadline passes.
// Memory: `bytes` shared, plus what fork copies on write. Thread-safe (each call its own child).
// Dissertation: none (robust reading of archives). Throws IoError when the mapping or the fork
// fails; reports the child's failures in the result.
#pragma once
#include <cstddef>
#include <functional>
#include <string>

namespace meshless {

struct IsolatedResult {
    enum class Outcome { ok, error, crashed, timed_out };
    Outcome outcome = Outcome::ok;
    int signal = 0;        ///< crashed: the signal that ended the child
    std::string message;   ///< error: the child's exception text (one line, at most 1 KiB)
};

/// Runs work(buffer of `bytes`) in a child process; on Outcome::ok the buffer is copied to `out`.
/// `timeout_seconds` > 0: a child still running then is killed (Outcome::timed_out).
IsolatedResult run_isolated(std::size_t bytes, std::byte* out, const std::function<void(std::byte*)>& work, int timeout_seconds);

}  // namespace meshless
