#include "formats/binary_file.hpp"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>

#include "kernels/errors.hpp"

namespace meshless {

namespace {
struct FileCloser {
    void operator()(std::FILE* f) const { std::fclose(f); }
};
using FilePtr = std::unique_ptr<std::FILE, FileCloser>;

FilePtr open_regular(const std::string& path) {
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec))
        throw IoError(path + ": is a directory, expected a file");
    FilePtr f(std::fopen(path.c_str(), "rb"));
    if (!f) throw IoError(path + ": cannot open: " + std::strerror(errno));
    return f;
}
}  // namespace

std::uint64_t regular_file_size(const std::string& path) {
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec))
        throw IoError(path + ": is a directory, expected a file");
    const auto s = std::filesystem::file_size(path, ec);
    if (ec) throw IoError(path + ": cannot open: " + ec.message());
    return s;
}

void read_file_range_into(const std::string& path, std::uint64_t offset, std::uint64_t count, std::byte* dst) {
    FilePtr f = open_regular(path);
    const std::uint64_t size = regular_file_size(path);
    if (offset > size || count > size - offset)
        throw FormatError(path + ": truncated: need " + std::to_string(count) + " bytes at offset " +
                          std::to_string(offset) + ", file has " + std::to_string(size));
    if (count == 0) return;
    if (fseeko(f.get(), static_cast<off_t>(offset), SEEK_SET) != 0)
        throw IoError(path + ": cannot seek to " + std::to_string(offset) + ": " + std::strerror(errno));
    const std::size_t got = std::fread(dst, 1, static_cast<std::size_t>(count), f.get());
    if (got != count)
        throw IoError(path + ": read failed at offset " + std::to_string(offset + got) + ": " +
                      (std::ferror(f.get()) ? std::strerror(errno) : "unexpected end of file"));
}

std::vector<std::byte> read_file_range(const std::string& path, std::uint64_t offset, std::uint64_t count) {
    // validate before allocating (a corrupt header can ask for absurd sizes)
    const std::uint64_t size = regular_file_size(path);
    if (offset > size || count > size - offset)
        throw FormatError(path + ": truncated: need " + std::to_string(count) + " bytes at offset " +
                          std::to_string(offset) + ", file has " + std::to_string(size));
    std::vector<std::byte> out(static_cast<std::size_t>(count));
    read_file_range_into(path, offset, count, out.data());
    return out;
}

std::vector<std::byte> read_file_bytes(const std::string& path) {
    return read_file_range(path, 0, regular_file_size(path));
}

std::string read_file_prefix(const std::string& path, std::size_t max_bytes) {
    FilePtr f = open_regular(path);
    std::string s(max_bytes, '\0');
    const std::size_t got = std::fread(s.data(), 1, max_bytes, f.get());
    if (std::ferror(f.get())) throw IoError(path + ": read failed: " + std::strerror(errno));
    s.resize(got);
    return s;
}

}  // namespace meshless
