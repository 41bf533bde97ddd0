#include "ooc/brick_store_values.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "kernels/morton.hpp"

namespace meshless {

void brick_store_values(const BrickStore& store, const BrickStoreField& field, std::span<const Vec3> p, std::span<double> value) {
    const BrickStoreInfo& info = store.info();
    const GridSpec& g = info.grid;
    const auto B = static_cast<std::int64_t>(info.brick_edge);
    std::int64_t last[3];
    for (int a = 0; a < 3; ++a) last[a] = std::max<std::int64_t>(0, g.dims[a] - 2);
    // each position's brick: the one owning its cell, the cell as the field picks it (clamped to the grid)
    struct Item {
        std::uint64_t key;
        std::uint64_t index;
    };
    std::vector<Item> items(p.size());
    for (std::size_t n = 0; n < p.size(); ++n) {
        std::uint32_t b[3];
        for (int a = 0; a < 3; ++a) {
            const double f = std::floor((p[n][a] - g.origin[a]) / g.spacing[a]);
            const std::int64_t cell = !(f >= 0) ? 0 : f > static_cast<double>(last[a]) ? last[a] : static_cast<std::int64_t>(f);
            b[a] = static_cast<std::uint32_t>(std::min<std::int64_t>(cell / B, info.bricks_per_axis[a] - 1));
        }
        items[n] = Item{morton_encode(b[0], b[1], b[2]), n};
    }
    std::sort(items.begin(), items.end(), [](const Item& x, const Item& y) { return x.key != y.key ? x.key < y.key : x.index < y.index; });
    std::vector<Vec3> grouped(p.size());
    for (std::size_t i = 0; i < items.size(); ++i) grouped[i] = p[items[i].index];
    std::vector<double> v(p.size());
    field.evaluate(grouped, v, {});
    for (std::size_t i = 0; i < items.size(); ++i) value[items[i].index] = v[i];
}

}  // namespace meshless
