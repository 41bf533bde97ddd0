#include "formats/file_names.hpp"

#include <filesystem>
#include <string_view>

#include "formats/text_header.hpp"

namespace meshless {

std::string lower_extension(const std::string& path) { return to_lower(std::filesystem::path(path).extension().string()); }

bool ends_with_ci(const std::string& path, const char* suffix) {
    const std::size_t n = std::char_traits<char>::length(suffix);
    return path.size() >= n && to_lower(std::string_view(path).substr(path.size() - n)) == suffix;
}

std::string joined_names(const std::vector<std::string>& paths) {
    std::string s;
    for (const auto& p : paths) {
        if (!s.empty()) s += ',';
        s += std::filesystem::path(p).filename().string();
    }
    return s;
}

}  // namespace meshless
