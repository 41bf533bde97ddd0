#include "kernels/mesh_normals.hpp"

#include <cmath>
#include <stdexcept>

namespace meshless {

std::vector<float> area_weighted_normals(const Mesh& m) {
    const std::size_t nv = m.vertex_count();
    std::vector<double> sum(3 * nv, 0.0);
    for (std::size_t t = 0; t + 2 < m.tri.size(); t += 3) {
        const std::uint32_t i[3] = {m.tri[t], m.tri[t + 1], m.tri[t + 2]};
        for (std::uint32_t v : i)
            if (v >= nv) throw std::out_of_range("area_weighted_normals: triangle index beyond the vertices");
        double e1[3], e2[3];
        for (int a = 0; a < 3; ++a) {
            e1[a] = double(m.xyz[3 * i[1] + a]) - m.xyz[3 * i[0] + a];
            e2[a] = double(m.xyz[3 * i[2] + a]) - m.xyz[3 * i[0] + a];
        }
        const double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
        for (std::uint32_t v : i)
            for (int a = 0; a < 3; ++a) sum[3 * v + a] += n[a];
    }
    std::vector<float> out(3 * nv, 0.0f);
    for (std::size_t v = 0; v < nv; ++v) {
        const double len = std::sqrt(sum[3 * v] * sum[3 * v] + sum[3 * v + 1] * sum[3 * v + 1] + sum[3 * v + 2] * sum[3 * v + 2]);
        if (!(len > 0) || !std::isfinite(len)) continue;
        for (int a = 0; a < 3; ++a) out[3 * v + a] = static_cast<float>(sum[3 * v + a] / len);
    }
    return out;
}

}  // namespace meshless
