#include "ooc/brick_marching_cubes.hpp"

#include <cstring>
#include <unordered_map>

namespace meshless {

namespace {

struct PosKey {
    std::uint32_t b[3];
    bool operator==(const PosKey& o) const { return b[0] == o.b[0] && b[1] == o.b[1] && b[2] == o.b[2]; }
};
struct PosHash {
    std::size_t operator()(const PosKey& k) const {
        return (std::size_t{k.b[0]} * 0x9E3779B97F4A7C15ull) ^ (std::size_t{k.b[1]} * 0xC2B2AE3D27D4EB4Full) ^
               (std::size_t{k.b[2]} * 0x165667B19E3779F9ull);
    }
};

}  // namespace

Mesh marching_cubes_bricks(const BrickStore& store, BrickCache& cache, const BrickIndex& index, double iso,
                           McStats* stats) {
    Mesh out;
    McStats total;
    const GridSpec& whole = store.info().grid;
    // vertices on brick faces, by exact position, -> index in `out`
    std::unordered_map<PosKey, std::uint32_t, PosHash> seam;
    for (const std::size_t b : index.active(iso)) {
        const auto bytes = cache.get(b);
        VolumeView v = cache.view(b, *bytes);
        v.grid.origin = whole.origin;
        const auto first = store.brick_first_voxel(b);
        McStats st;
        const Mesh m = marching_cubes_slab(v, iso, 0, v.grid.dims[2] - 1, &st, first);
        total.active_cells += st.active_cells;
        total.skipped_nonfinite += st.skipped_nonfinite;
        // the brick's boundary planes, computed as marching cubes computes positions
        float lo[3], hi[3];
        for (int d = 0; d < 3; ++d) {
            lo[d] = static_cast<float>(whole.origin[d] + whole.spacing[d] * static_cast<double>(first[d]));
            hi[d] = static_cast<float>(whole.origin[d] + whole.spacing[d] * static_cast<double>(first[d] + v.grid.dims[d] - 1));
        }
        std::vector<std::uint32_t> remap(m.vertex_count());
        for (std::size_t i = 0; i < m.vertex_count(); ++i) {
            const float* p = &m.xyz[3 * i];
            const bool on_face = p[0] == lo[0] || p[0] == hi[0] || p[1] == lo[1] || p[1] == hi[1] || p[2] == lo[2] || p[2] == hi[2];
            const auto fresh = static_cast<std::uint32_t>(out.vertex_count());
            if (on_face) {
                PosKey k;
                std::memcpy(k.b, p, sizeof k.b);
                const auto [it, inserted] = seam.emplace(k, fresh);
                if (!inserted) {
                    remap[i] = it->second;
                    continue;
                }
            }
            remap[i] = fresh;
            out.xyz.insert(out.xyz.end(), p, p + 3);
            out.normals.insert(out.normals.end(), &m.normals[3 * i], &m.normals[3 * i] + 3);
        }
        for (std::uint32_t t : m.tri) out.tri.push_back(remap[t]);
    }
    if (stats) *stats = total;
    return out;
}

}  // namespace meshless
