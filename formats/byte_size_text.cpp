#include "formats/byte_size_text.hpp"

#include <cstdio>

namespace meshless {

std::string byte_size_text(std::uint64_t bytes) {
    static const char* const kUnit[] = {"bytes", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB"};
    double v = static_cast<double>(bytes);
    int u = 0;
    while (v >= 1024 && u < 6) v /= 1024, ++u;
    char b[48];
    if (u == 0) std::snprintf(b, sizeof b, "%llu bytes", static_cast<unsigned long long>(bytes));
    else std::snprintf(b, sizeof b, "%.1f %s", v, kUnit[u]);
    return b;
}

}  // namespace meshless
