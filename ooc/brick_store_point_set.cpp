#include "ooc/brick_store_point_set.hpp"

#include <cmath>
#include <filesystem>
#include <vector>

#include "ooc/brick_store.hpp"

namespace meshless {

PointSet point_set_from_brick_store(const std::string& path) {
    const auto store = BrickStore::open(path);
    const BrickStoreInfo& info = store->info();
    const GridSpec& g = info.grid;
    PointSet ps;
    ps.pos.reserve(static_cast<std::size_t>(g.voxel_count()));
    ps.value.reserve(static_cast<std::size_t>(g.voxel_count()));
    std::vector<std::byte> buf;
    const std::int64_t B = info.brick_edge;
    for (std::size_t b = 0; b < store->bricks().size(); ++b) {
        store->read_brick(b, buf);
        const GridSpec bg = store->brick_grid(b);
        const auto first = store->brick_first_voxel(b);
        const VolumeView v{buf.data(), info.type, bg};
        std::int64_t own[3];
        for (int a = 0; a < 3; ++a) own[a] = first[a] + B >= g.dims[a] - 1 ? bg.dims[a] : std::min<std::int64_t>(B, bg.dims[a]);
        for (std::int64_t k = 0; k < own[2]; ++k)
            for (std::int64_t j = 0; j < own[1]; ++j)
                for (std::int64_t i = 0; i < own[0]; ++i) {
                    const double f = v.at(i, j, k);
                    const Vec3 p{bg.origin[0] + i * bg.spacing[0], bg.origin[1] + j * bg.spacing[1], bg.origin[2] + k * bg.spacing[2]};
                    if (!std::isfinite(f) || !std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
                        ++ps.dropped_nonfinite;
                        continue;
                    }
                    ps.pos.push_back(p);
                    ps.value.push_back(f);
                }
    }
    ps.value_name = "value";
    ps.blocks.push_back(PointSetBlock{std::filesystem::path(path).filename().string(), g.dims, 0, ps.pos.size()});
    return ps;
}

}  // namespace meshless
