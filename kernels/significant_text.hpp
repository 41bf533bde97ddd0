// Numbers as text with a chosen count of significant digits (formats/text_header.hpp number_text gives
// the shortest text that reads back): printf's "%.*g" with a chosen number of significant
// digits (17 round-trips a double, 9 a float, 6 reads well in a message, 3 fits a legend).
// Pure; throws only std::bad_alloc. Dissertation: none.
#pragma once
#include <cstdio>
#include <string>

namespace meshless {

inline std::string significant_text(double v, int digits) {
    char b[48];
    std::snprintf(b, sizeof b, "%.*g", digits, v);
    return b;
}

}  // namespace meshless
