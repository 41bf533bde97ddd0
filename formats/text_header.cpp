#include "formats/text_header.hpp"

#include <cctype>
#include <charconv>
#include <cstdlib>
#include <filesystem>

#include "formats/ply.hpp"
#include "kernels/errors.hpp"

namespace meshless {

std::vector<std::int64_t> file_range_indices(std::int64_t a, std::int64_t b, std::int64_t s, const std::string& path,
                                             const char* field) {
    constexpr std::int64_t kMaxFiles = std::int64_t{1} << 20;
    std::int64_t span = 0;
    const bool bad = s == 0 || __builtin_sub_overflow(b, a, &span) || span == INT64_MIN || (span != 0 && (span < 0) != (s < 0)) ||
                     (s == INT64_MIN ? 0 : span / s) >= kMaxFiles;
    if (bad)
        throw FormatError(path + ": bad " + field + " range " + std::to_string(a) + " " + std::to_string(b) + " " +
                          std::to_string(s) + " (a step toward max, at most " + std::to_string(kMaxFiles) + " files)");
    const std::int64_t count = (s == INT64_MIN ? 0 : span / s) + 1;
    std::vector<std::int64_t> out;
    out.reserve(static_cast<std::size_t>(count));
    for (std::int64_t c = 0; c < count; ++c) out.push_back(a + c * s);  // within [min, max]: no overflow
    return out;
}

std::string escape_field(std::string_view s, std::size_t max) { return ply_escape(s, max); }

std::string line_breaks_escaped(std::string_view s) {
    std::string out;
    out.reserve(s.size());
    for (const char c : s) {
        if (c == '\n') out += "\\x0a";
        else out += c;
    }
    return out;
}

std::string trim(std::string_view s) {
    std::size_t a = 0, b = s.size();
    while (a < b && std::isspace(static_cast<unsigned char>(s[a]))) ++a;
    while (b > a && (std::isspace(static_cast<unsigned char>(s[b - 1])) || s[b - 1] == '\0')) --b;
    return std::string(s.substr(a, b - a));
}

std::string number_text(double v) {
    char buf[32];
    const auto r = std::to_chars(buf, buf + sizeof buf, v);
    return std::string(buf, r.ptr);
}

std::string to_lower(std::string_view s) {
    std::string r(s);
    for (auto& c : r) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return r;
}

std::vector<std::string> split_ws(std::string_view s) {
    std::vector<std::string> out;
    std::size_t i = 0;
    while (i < s.size()) {
        while (i < s.size() && std::isspace(static_cast<unsigned char>(s[i]))) ++i;
        std::size_t j = i;
        while (j < s.size() && !std::isspace(static_cast<unsigned char>(s[j]))) ++j;
        if (j > i) out.emplace_back(s.substr(i, j - i));
        i = j;
    }
    return out;
}

std::vector<std::string> split_lines(std::string_view s) {
    std::vector<std::string> out;
    std::size_t i = 0;
    while (i <= s.size()) {
        std::size_t j = s.find('\n', i);
        if (j == std::string_view::npos) j = s.size();
        std::string_view l = s.substr(i, j - i);
        if (!l.empty() && l.back() == '\r') l.remove_suffix(1);
        out.emplace_back(l);
        if (j == s.size()) break;
        i = j + 1;
    }
    return out;
}

double parse_double(const std::string& tok, const std::string& path, const char* field) {
    const std::string t = trim(tok);
    if (t.empty()) throw FormatError(path + ": bad " + field + " '': expected a number");
    char* end = nullptr;
    const double v = std::strtod(t.c_str(), &end);
    if (end != t.c_str() + t.size())
        throw FormatError(path + ": bad " + field + " '" + ply_escape(t) + "': expected a number");
    return v;
}

std::int64_t parse_int(const std::string& tok, const std::string& path, const char* field) {
    const std::string t = trim(tok);
    std::int64_t v = 0;
    const char* b = t.data();
    if (!t.empty() && t[0] == '+') ++b;
    const auto r = std::from_chars(b, t.data() + t.size(), v);
    if (t.empty() || r.ec != std::errc() || r.ptr != t.data() + t.size())
        throw FormatError(path + ": bad " + field + " '" + ply_escape(t) + "': expected an integer");
    return v;
}

namespace {
std::vector<std::string> tokens(std::string_view text) {
    std::string t(text);
    for (auto& c : t)
        if (c == ',') c = ' ';
    return split_ws(t);
}
}  // namespace

std::vector<double> parse_doubles(std::string_view text, std::size_t n, const std::string& path, const char* field) {
    const auto tk = tokens(text);
    if (tk.size() != n)
        throw FormatError(path + ": bad " + field + " '" + ply_escape(trim(text)) + "': expected " + std::to_string(n) + " numbers");
    std::vector<double> v;
    for (const auto& t : tk) v.push_back(parse_double(t, path, field));
    return v;
}

std::vector<std::int64_t> parse_ints(std::string_view text, std::size_t n, const std::string& path, const char* field) {
    const auto tk = tokens(text);
    if (tk.size() != n)
        throw FormatError(path + ": bad " + field + " '" + ply_escape(trim(text)) + "': expected " + std::to_string(n) + " integers");
    std::vector<std::int64_t> v;
    for (const auto& t : tk) v.push_back(parse_int(t, path, field));
    return v;
}

bool parse_bool(const std::string& tok, const std::string& path, const char* field) {
    const std::string l = to_lower(trim(tok));
    if (l == "true" || l == "1" || l == "yes") return true;
    if (l == "false" || l == "0" || l == "no") return false;
    throw FormatError(path + ": bad " + field + " '" + ply_escape(trim(tok)) + "': expected True or False");
}

// "quarter.%d" with one integer conversion -> formatted name; rejects anything else.
std::string format_file_pattern(const std::string& fmt, std::int64_t i, const std::string& path) {
    std::string out;
    int conversions = 0;
    for (std::size_t p = 0; p < fmt.size(); ++p) {
        if (fmt[p] != '%') {
            out += fmt[p];
            continue;
        }
        if (p + 1 < fmt.size() && fmt[p + 1] == '%') {
            out += '%';
            ++p;
            continue;
        }
        std::size_t q = p + 1;
        bool zero = false;
        if (q < fmt.size() && fmt[q] == '0') zero = true, ++q;
        int width = 0;
        // widths above 32 are refused below; stop growing there (a long digit run must not overflow)
        while (q < fmt.size() && std::isdigit(static_cast<unsigned char>(fmt[q]))) {
            if (width <= 32) width = width * 10 + (fmt[q] - '0');
            ++q;
        }
        if (q >= fmt.size() || (fmt[q] != 'd' && fmt[q] != 'i' && fmt[q] != 'u') || width > 32)
            throw FormatError(path + ": bad data file pattern '" + ply_escape(fmt) + "': expected one %d conversion");
        // the magnitude in unsigned arithmetic: -i overflows for the smallest int64
        std::string num = std::to_string(i < 0 ? std::uint64_t{0} - static_cast<std::uint64_t>(i) : static_cast<std::uint64_t>(i));
        const std::size_t len = num.size() + (i < 0 ? 1 : 0);
        if (static_cast<std::size_t>(width) > len) num.insert(0, width - len, zero ? '0' : ' ');
        if (i < 0) num.insert(zero ? 0 : num.find_first_not_of(' '), 1, '-');
        out += num;
        ++conversions;
        p = q;
    }
    if (conversions != 1)
        throw FormatError(path + ": bad data file pattern '" + ply_escape(fmt) + "': expected exactly one %d conversion");
    return out;
}

std::string parent_dir(const std::string& path) {
    const auto p = std::filesystem::path(path).parent_path();
    return p.empty() ? std::string(".") : p.string();
}

std::string resolve_relative(const std::string& header_path, const std::string& name) {
    const std::filesystem::path n(name);
    if (n.is_absolute()) return name;
    return (std::filesystem::path(parent_dir(header_path)) / n).string();
}

}  // namespace meshless
