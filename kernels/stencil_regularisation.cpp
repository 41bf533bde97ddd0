#include "kernels/stencil_regularisation.hpp"

#include <cassert>
#include <cmath>
#include <limits>

namespace meshless {

void regularise_block(const BinningGrid& g, const BinnedPoints& bins, const Field& f, const std::array<std::int64_t, 3>& lo,
                      const std::array<std::int64_t, 3>& hi, RegularisedBlock& out, const PointCoverage* coverage) {
    for (int a = 0; a < 3; ++a) assert(0 <= lo[static_cast<std::size_t>(a)] && lo[static_cast<std::size_t>(a)] <= hi[static_cast<std::size_t>(a)] &&
                                       hi[static_cast<std::size_t>(a)] < g.dims[static_cast<std::size_t>(a)]);
    out.lo = lo;
    out.hi = hi;
    const std::size_t n = static_cast<std::size_t>((hi[0] - lo[0] + 1) * (hi[1] - lo[1] + 1) * (hi[2] - lo[2] + 1));
    out.value.assign(n, std::numeric_limits<double>::quiet_NaN());
    std::vector<Vec3> at;
    std::vector<std::size_t> slot;
    std::size_t s = 0;
    for (std::int64_t k = lo[2]; k <= hi[2]; ++k)
        for (std::int64_t j = lo[1]; j <= hi[1]; ++j)
            for (std::int64_t i = lo[0]; i <= hi[0]; ++i, ++s) {
                const auto c = static_cast<std::size_t>(g.index(i, j, k));
                if (bins.start[c + 1] != bins.start[c]) continue;
                at.push_back(g.cell_centre(i, j, k));
                slot.push_back(s);
            }
    out.evaluations = static_cast<std::int64_t>(at.size());
    out.uncovered = 0;
    if (at.empty()) return;
    std::vector<double> v(at.size());
    f.evaluate(at, v, {});
    if (coverage) out.uncovered = static_cast<std::int64_t>(coverage->mask(at, v, {}));
    for (std::size_t i = 0; i < at.size(); ++i) out.value[slot[i]] = v[i];
}

}  // namespace meshless
