#include "formats/field_hint.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <vector>

namespace meshless {

namespace {

constexpr std::string_view kKey = "meshless field: hardy-c-rel ";
constexpr std::size_t kHeadBytes = 64 * 1024;

}  // namespace

std::string field_hint_line(double hardy_c_rel) {
    char buf[64];
    for (int digits = 15; digits <= 17; ++digits) {  // the shortest that reads back the same double
        std::snprintf(buf, sizeof buf, "%.*g", digits, hardy_c_rel);
        if (std::strtod(buf, nullptr) == hardy_c_rel) break;
    }
    return std::string(kKey) + buf;
}

std::optional<double> parse_field_hint(std::string_view text) {
    const std::size_t at = text.find(kKey);
    if (at == std::string_view::npos) return std::nullopt;
    std::string number;
    for (std::size_t i = at + kKey.size(); i < text.size() && number.size() < 40; ++i) {
        const char c = text[i];
        if ((c >= '0' && c <= '9') || c == '.' || c == 'e' || c == 'E' || c == '-' || c == '+') number += c;
        else break;
    }
    if (number.empty()) return std::nullopt;
    char* end = nullptr;
    const double c = std::strtod(number.c_str(), &end);
    if (end != number.c_str() + number.size() || !std::isfinite(c) || !(c > 0) || c > 100) return std::nullopt;
    return c;
}

std::optional<double> point_file_field_hint(const std::string& path) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) return std::nullopt;  // a FIFO or stdin is not read twice
    std::ifstream in(path, std::ios::binary);
    if (!in) return std::nullopt;
    std::vector<char> head(kHeadBytes);
    in.read(head.data(), static_cast<std::streamsize>(head.size()));
    const std::string_view text(head.data(), static_cast<std::size_t>(in.gcount()));
    if (text.starts_with("ply")) {  // header comments only
        const std::size_t end = text.find("end_header");
        const std::string_view header = text.substr(0, end);
        for (std::size_t at = header.find("\ncomment "); at != std::string_view::npos; at = header.find("\ncomment ", at + 1)) {
            const std::size_t eol = header.find('\n', at + 1);
            if (auto c = parse_field_hint(header.substr(at + 9, eol == std::string_view::npos ? std::string_view::npos : eol - at - 9)))
                return c;
        }
        return std::nullopt;
    }
    if (text.starts_with("<?xml") || text.starts_with("<!--") || text.starts_with("<VTKFile")) {  // comments before VTKFile
        const std::size_t root = text.find("<VTKFile");
        const std::string_view prolog = text.substr(0, root);
        for (std::size_t at = prolog.find("<!--"); at != std::string_view::npos; at = prolog.find("<!--", at + 4)) {
            const std::size_t close = prolog.find("-->", at + 4);
            if (close == std::string_view::npos) break;
            if (auto c = parse_field_hint(prolog.substr(at + 4, close - at - 4))) return c;
        }
    }
    return std::nullopt;
}

}  // namespace meshless
