// An input named on a command line or by a caller, opened for reading: "-" is standard input
// (Unix habits), anything else a regular file. Throws IoError naming the path when it is a
// folder, not a regular file, or cannot be opened.
#pragma once
#include <cstdio>
#include <string>

namespace meshless {

/// A FILE* for reading: stdin for "-", else fopen (IoError naming the path; directories refused).
struct InputFile {
    std::FILE* f = nullptr;
    std::string name;
    explicit InputFile(const std::string& path);
    ~InputFile();
    InputFile(const InputFile&) = delete;
    InputFile& operator=(const InputFile&) = delete;
};

}  // namespace meshless
