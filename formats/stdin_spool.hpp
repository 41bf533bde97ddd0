// `-` as a volume input (Unix habits): standard input copied once into an unlinked
// temporary file in $TMPDIR (or /tmp), so that the readers, which dispatch on content (NRRD, MHA,
// VTK legacy and VTI magic; raw with --dims and --type) and may map or reopen their input, read it
// as a file: path() is /proc/self/fd/N while the spool lives. Nothing is left on disk at any exit
// (the file is unlinked before the first byte is written). readable_errors() runs a read and
// rewrites the spool's path in library errors to "- (stdin)". Memory: a 1 MiB copy buffer.
// Throws IoError when the temporary cannot be made or written, or when stdin is a terminal.
#pragma once
#include <cstdio>
#include <functional>
#include <string>

namespace meshless {

class StdinSpool {
public:
    StdinSpool();
    ~StdinSpool();
    StdinSpool(const StdinSpool&) = delete;
    StdinSpool& operator=(const StdinSpool&) = delete;
    const std::string& path() const { return path_; }
    /// Runs f; FormatError, IoError and InvalidArgument from it are rethrown (same type) with
    /// path() replaced by "- (stdin)".
    template <class F>
    auto readable_errors(F&& f) const -> decltype(f());

private:
    [[noreturn]] void rethrow_renamed() const;
    std::FILE* file_ = nullptr;  ///< formats/temporary_files.hpp unlinked_temporary; written through fd_
    int fd_ = -1;
    std::string path_;
};

template <class F>
auto StdinSpool::readable_errors(F&& f) const -> decltype(f()) {
    try {
        return f();
    } catch (...) {
        rethrow_renamed();
    }
}

}  // namespace meshless
