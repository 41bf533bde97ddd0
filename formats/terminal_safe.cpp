#include "formats/terminal_safe.hpp"

#include <algorithm>
#include <cstdio>

namespace meshless {

std::string terminal_safe(std::string_view s, std::size_t max) {
    std::string out;
    const std::size_t n = std::min(s.size(), max);
    for (std::size_t i = 0; i < n; ++i) {
        const auto c = static_cast<unsigned char>(s[i]);
        // C0 controls (ESC, CR, newlines, ...), DEL, and the UTF-8 form of the C1 controls (CSI ...)
        const bool c1 = c == 0xC2 && i + 1 < n && static_cast<unsigned char>(s[i + 1]) >= 0x80 &&
                        static_cast<unsigned char>(s[i + 1]) <= 0x9F;
        if (c < 0x20 || c == 0x7F || c1) {
            char x[8];
            std::snprintf(x, sizeof x, "\\x%02x", c);
            out += x;
            if (c1) {
                std::snprintf(x, sizeof x, "\\x%02x", static_cast<unsigned char>(s[++i]));
                out += x;
            }
        } else {
            out += static_cast<char>(c);
        }
    }
    if (s.size() > max) out += "...";
    return out;
}

}  // namespace meshless
