#include "formats/transfer_function_file.hpp"
#include "formats/binary_file.hpp"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

#include "kernels/errors.hpp"

namespace meshless {

namespace {

constexpr std::size_t kMaxRows = 65536;
constexpr std::size_t kMaxLine = 4096;

/// Printable form of a token for messages (control and non-ASCII bytes escaped, at most 40 bytes).
std::string shown(std::string_view s) {
    std::string out;
    for (std::size_t i = 0; i < s.size() && i < 40; ++i) {
        const auto c = static_cast<unsigned char>(s[i]);
        if (c >= 0x20 && c < 0x7f) out += static_cast<char>(c);
        else {
            char buf[8];
            std::snprintf(buf, sizeof buf, "\\x%02x", c);
            out += buf;
        }
    }
    if (s.size() > 40) out += "...";
    return out;
}

}  // namespace

TransferFunction parse_transfer_function(std::string_view text, const std::string& name) {
    std::vector<TransferPoint> pts;
    std::size_t line_no = 0, pos = 0;
    const char* what[5] = {"value", "r", "g", "b", "a"};
    while (pos < text.size()) {
        ++line_no;
        std::size_t end = text.find('\n', pos);
        if (end == std::string_view::npos) end = text.size();
        std::string line(text.substr(pos, end - pos));
        pos = end + 1;
        const std::string where = name + ":" + std::to_string(line_no) + ": ";
        if (line.size() > kMaxLine) throw FormatError(where + "line longer than 4096 bytes");
        if (const auto hash = line.find('#'); hash != std::string::npos) line.resize(hash);
        for (char& c : line)
            if (c == ',' || c == '\t' || c == '\r') c = ' ';
        std::istringstream ls(line);
        std::vector<std::string> tok;
        for (std::string t; ls >> t;) tok.push_back(t);
        if (tok.empty()) continue;
        if (tok.size() != 5)
            throw FormatError(where + "expected 5 numbers 'value r g b a', got " + std::to_string(tok.size()) + " fields");
        double v[5];
        for (int i = 0; i < 5; ++i) {
            const char* s = tok[static_cast<std::size_t>(i)].c_str();
            char* e = nullptr;
            errno = 0;
            v[i] = std::strtod(s, &e);
            if (e == s || *e != '\0' || !std::isfinite(v[i]))
                throw FormatError(where + what[i] + " '" + shown(tok[static_cast<std::size_t>(i)]) + "' is not a finite number");
            if (i > 0 && !(v[i] >= 0.0 && v[i] <= 1.0))
                throw FormatError(where + what[i] + " = " + shown(tok[static_cast<std::size_t>(i)]) + " lies outside [0, 1]");
        }
        if (!pts.empty() && v[0] < pts.back().value)
            throw FormatError(where + "value " + shown(tok[0]) + " is below the previous row's: rows must be sorted by value");
        if (pts.size() == kMaxRows) throw FormatError(where + "more than 65536 rows");
        pts.push_back({v[0], v[1], v[2], v[3], v[4]});
    }
    if (pts.empty()) throw FormatError(name + ": no 'value r g b a' rows (an empty transfer function)");
    return TransferFunction(std::move(pts));
}

TransferFunction read_transfer_function_file(const std::string& path) {
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec)) throw IoError(path + ": is a directory, expected a transfer-function file");
    require_regular_file(path);
    std::ifstream in(path, std::ios::binary);
    if (!in) throw IoError(path + ": cannot open (" + std::strerror(errno) + ")");
    // bounded read: 65536 rows of at most 4096 bytes (plus blank/comment lines) is far more than any
    // transfer function needs; refuse bigger files before reading them whole
    const auto size = std::filesystem::file_size(path, ec);
    if (!ec && size > (std::uint64_t{64} << 20)) throw FormatError(path + ": larger than 64 MiB, not a transfer-function file");
    std::ostringstream buf;
    buf << in.rdbuf();
    return parse_transfer_function(buf.str(), path);
}

}  // namespace meshless
