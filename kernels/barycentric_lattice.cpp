#include "kernels/barycentric_lattice.hpp"

#include <string>

#include "kernels/errors.hpp"

namespace meshless {

std::vector<std::array<double, 3>> barycentric_lattice(int n) {
    if (n < 1 || n > kMaxLatticeN)
        throw InvalidArgument("barycentric lattice: n must be 1.." + std::to_string(kMaxLatticeN) + ", got " + std::to_string(n));
    std::vector<std::array<double, 3>> w;
    w.reserve(lattice_size(n));
    const double inv = 1.0 / n;
    for (int i = n - 1; i >= 0; --i)
        for (int j = n - 1 - i; j >= 0; --j) {
            const int k = n - 1 - i - j;
            w.push_back({(i + 1.0 / 3.0) * inv, (j + 1.0 / 3.0) * inv, (k + 1.0 / 3.0) * inv});
        }
    return w;
}

}  // namespace meshless
