// Paths the tests need: the shared real-data folder and the built `meshless` executable.
#pragma once
#include <filesystem>
#include <string>
#include <cstdint>
#include <unistd.h>

namespace meshless::test {

/// ../shared/data beside the checkout (never copied into the repository).
inline std::filesystem::path shared_data() { return std::filesystem::path(MESHLESS_SHARED_DATA); }
inline bool have_shared_data() { return std::filesystem::exists(shared_data() / "SOURCES.md"); }
/// The built meshless executable.
inline std::string meshless_exe() { return MESHLESS_BINARY; }

/// A fresh empty directory under the system temp dir, removed by the destructor.
struct TempDir {
    std::filesystem::path path;
    explicit TempDir(const std::string& tag) {
        path = std::filesystem::temp_directory_path() /
               ("meshless-test-" + tag + "-" + std::to_string(::getpid()) + "-" +
                std::to_string(reinterpret_cast<std::uintptr_t>(this)));
        std::filesystem::remove_all(path);
        std::filesystem::create_directories(path);
    }
    ~TempDir() { std::error_code ec; std::filesystem::remove_all(path, ec); }
    std::filesystem::path operator/(const std::string& n) const { return path / n; }
};

}  // namespace meshless::test
