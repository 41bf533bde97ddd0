#include "formats/base64.hpp"

#include <array>
#include <cctype>

#include "kernels/errors.hpp"

namespace meshless {

namespace {
constexpr char kAlphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
constexpr std::array<signed char, 256> make_table() {
    std::array<signed char, 256> t{};
    for (auto& v : t) v = -1;
    for (int i = 0; i < 64; ++i) t[static_cast<unsigned char>(kAlphabet[i])] = static_cast<signed char>(i);
    t[static_cast<unsigned char>('=')] = -2;
    return t;
}
constexpr auto kTable = make_table();
}  // namespace

std::vector<std::byte> base64_decode(std::string_view text, const std::string& path, bool stop_at_other) {
    std::vector<std::byte> out;
    out.reserve(text.size() / 4 * 3 + 3);
    int quad[4];
    int nq = 0;
    auto flush = [&](int n) {
        // n chars collected (2..4), '=' marked as -2
        int valid = 0;
        while (valid < n && quad[valid] >= 0) ++valid;
        for (int k = valid; k < n; ++k)
            if (quad[k] != -2) throw FormatError(path + ": bad base64: data after padding");
        if (valid < 2) throw FormatError(path + ": bad base64: incomplete group");
        const unsigned v = (unsigned(quad[0]) << 18) | (unsigned(quad[1]) << 12) |
                           (unsigned(valid > 2 ? quad[2] : 0) << 6) | unsigned(valid > 3 ? quad[3] : 0);
        out.push_back(std::byte(v >> 16));
        if (valid > 2) out.push_back(std::byte((v >> 8) & 0xff));
        if (valid > 3) out.push_back(std::byte(v & 0xff));
    };
    for (std::size_t i = 0; i < text.size(); ++i) {
        const unsigned char c = static_cast<unsigned char>(text[i]);
        const int v = kTable[c];
        if (v == -1) {
            if (std::isspace(c)) continue;
            if (stop_at_other) break;
            throw FormatError(path + ": bad base64 character '" + std::string(1, static_cast<char>(c)) + "' at offset " +
                              std::to_string(i));
        }
        quad[nq++] = v;
        if (nq == 4) {
            flush(4);
            nq = 0;
        }
    }
    if (nq == 1) throw FormatError(path + ": bad base64: truncated group at the end");
    if (nq > 1) flush(nq);
    return out;
}

std::string base64_encode(const void* data, std::size_t n) {
    const auto* p = static_cast<const unsigned char*>(data);
    std::string s;
    s.reserve((n + 2) / 3 * 4);
    for (std::size_t i = 0; i < n; i += 3) {
        const unsigned v = (unsigned(p[i]) << 16) | (i + 1 < n ? unsigned(p[i + 1]) << 8 : 0u) | (i + 2 < n ? p[i + 2] : 0u);
        s += kAlphabet[(v >> 18) & 63];
        s += kAlphabet[(v >> 12) & 63];
        s += i + 1 < n ? kAlphabet[(v >> 6) & 63] : '=';
        s += i + 2 < n ? kAlphabet[v & 63] : '=';
    }
    return s;
}

}  // namespace meshless
