#include "formats/input_file.hpp"

#include <cerrno>
#include <cstring>
#include <filesystem>

#include "formats/binary_file.hpp"
#include "kernels/errors.hpp"

namespace meshless {

InputFile::InputFile(const std::string& path) : name(path) {
    if (path == "-") {
        f = stdin;
        return;
    }
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec)) throw IoError(path + ": is a directory, expected a file");
    require_regular_file(path);
    f = std::fopen(path.c_str(), "rb");
    if (!f) throw IoError(path + ": cannot open (" + std::strerror(errno) + ")");
}

InputFile::~InputFile() {
    if (f && f != stdin) std::fclose(f);
}

}  // namespace meshless
