// printf-style formatting into a std::string, for the one-line reports and warnings that recipes
// return to their front ends. docs/architecture.md "Libraries": recipes return text, front ends print.
// Throws nothing of its own (std::bad_alloc).
#pragma once
#include <algorithm>
#include <cstdio>
#include <string>

namespace meshless {

/// std::snprintf(fmt, args...) as a string of the exact length.
template <class... T>
std::string format_text(const char* fmt, T... args) {
    const int len = std::snprintf(nullptr, 0, fmt, args...);
    std::string s(static_cast<std::size_t>(std::max(len, 0)), '\0');
    std::snprintf(s.data(), s.size() + 1, fmt, args...);
    return s;
}

}  // namespace meshless
