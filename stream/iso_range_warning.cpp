#include "stream/iso_range_warning.hpp"

#include <cmath>

#include "formats/terminal_safe.hpp"

namespace meshless {

bool warn_if_iso_outside(double iso, const std::array<double, 2>& range, const std::string& source, std::FILE* out,
                         bool one_of_several) {
    if (std::isnan(range[0])) {
        std::fprintf(out, "meshless: warning: %s has no finite samples; the outputs will be empty\n", terminal_safe(source).c_str());
        return true;
    }
    if (iso < range[0] || iso > range[1]) {
        std::fprintf(out, "meshless: warning: %s: isovalue %g is outside the data range [%g, %g]; %s will be empty\n",
                     terminal_safe(source).c_str(), iso, range[0], range[1], one_of_several ? "its surface" : "the outputs");
        return true;
    }
    return false;
}

}  // namespace meshless
