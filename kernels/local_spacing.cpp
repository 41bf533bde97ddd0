#include "kernels/local_spacing.hpp"

#include <cmath>
#include <limits>
#include <vector>

namespace meshless {

double mean_neighbour_spacing(std::span<const Vec3> pos, std::span<const std::uint32_t> idx) {
    const std::size_t n = idx.size();
    if (n < 2) return 0.0;
    std::vector<double> best(n, std::numeric_limits<double>::infinity());
    for (std::size_t i = 0; i < n; ++i) {
        const Vec3 p = pos[idx[i]];
        double bi = best[i];
        for (std::size_t j = i + 1; j < n; ++j) {
            const Vec3 e = pos[idx[j]] - p;
            const double d2 = dot(e, e);
            if (d2 < bi) bi = d2;
            if (d2 < best[j]) best[j] = d2;
        }
        best[i] = bi;
    }
    double sum = 0;
    for (double b : best) sum += std::sqrt(b);
    return sum / static_cast<double>(n);
}

}  // namespace meshless
