// Output files that are never left half-written.
//
// AtomicFile writes to "<path>.tmp-<pid>" in the same directory and renames it over <path> on
// commit(); if the object is destroyed without commit() (an exception, a signal-free early return)
// the temporary is removed. The path "-" means standard output: written directly, commit() flushes.
// Throws IoError naming the path when the file cannot be created, written or renamed, or when the
// path is a directory. Not thread-safe; one writer per object.
#pragma once
#include <cstddef>
#include <cstdio>
#include <string>

namespace meshless {

class AtomicFile {
public:
    explicit AtomicFile(std::string path);
    ~AtomicFile();
    AtomicFile(const AtomicFile&) = delete;
    AtomicFile& operator=(const AtomicFile&) = delete;

    /// Appends bytes; throws IoError (or BrokenPipe when stdout's reader has gone).
    void write(const void* data, std::size_t n);
    void write(const std::string& s) { write(s.data(), s.size()); }
    /// Overwrites bytes at an absolute offset already written (not for stdout).
    void pwrite(std::size_t offset, const void* data, std::size_t n);
    /// Flushes, closes and renames into place. After commit() no more writes.
    void commit();
    std::FILE* handle() { return file_; }
    const std::string& path() const { return path_; }
    bool is_stdout() const { return path_ == "-"; }

private:
    std::string path_, tmp_;
    std::FILE* file_ = nullptr;
    bool committed_ = false;
};

}  // namespace meshless
