#include "ooc/brick_slice_source.hpp"

#include <algorithm>
#include <cstring>
#include <map>
#include <optional>

namespace meshless {

namespace {

class BrickStoreSliceSource final : public SliceSource {
public:
    explicit BrickStoreSliceSource(const std::string& path) : store_(BrickStore::open(path)), name_(path) {
        for (std::size_t i = 0; i < store_->bricks().size(); ++i) {
            const auto& c = store_->bricks()[i].coord;
            by_coord_[{c[0], c[1], c[2]}] = i;
        }
    }
    const GridSpec& grid() const override { return store_->info().grid; }
    SampleType type() const override { return store_->info().type; }
    std::string name() const override { return name_; }
    void restrict_xy(std::int64_t x0, std::int64_t x1, std::int64_t y0, std::int64_t y1) override {
        window_ = {x0, x1, y0, y1};
        current_ = ~0u;  // the layer in memory may lack bricks of the new window
    }

    void read_slices(std::int64_t k, std::int64_t count, std::byte* out) override {
        const GridSpec& g = grid();
        const std::size_t ss = sample_size(type());
        const std::size_t slice_bytes = static_cast<std::size_t>(g.dims[0] * g.dims[1]) * ss;
        const std::int64_t B = store_->info().brick_edge;
        const auto& per_axis = store_->info().bricks_per_axis;
        for (std::int64_t s = 0; s < count; ++s) {
            const std::int64_t z = k + s;
            const auto layer = static_cast<std::uint32_t>(std::min<std::int64_t>(z / B, per_axis[2] - 1));
            load_layer(layer);
            std::byte* dst = out + static_cast<std::size_t>(s) * slice_bytes;
            for (const auto& [i, bytes] : layer_) {
                const GridSpec bg = store_->brick_grid(i);
                const auto first = store_->brick_first_voxel(i);
                const std::int64_t lz = z - first[2];
                const std::size_t row = static_cast<std::size_t>(bg.dims[0]) * ss;
                for (std::int64_t y = 0; y < bg.dims[1]; ++y)
                    std::memcpy(dst + (static_cast<std::size_t>((first[1] + y) * g.dims[0] + first[0])) * ss,
                                bytes.data() + static_cast<std::size_t>((lz * bg.dims[1] + y)) * row, row);
            }
        }
    }

private:
    void load_layer(std::uint32_t layer) {
        if (layer == current_) return;
        layer_.clear();
        const auto& per_axis = store_->info().bricks_per_axis;
        for (std::uint32_t by = 0; by < per_axis[1]; ++by)
            for (std::uint32_t bx = 0; bx < per_axis[0]; ++bx) {
                const std::size_t i = by_coord_.at({bx, by, layer});
                if (window_) {  // only the bricks whose samples meet the window
                    const GridSpec bg = store_->brick_grid(i);
                    const auto first = store_->brick_first_voxel(i);
                    const auto& w = *window_;
                    if (first[0] > w[1] || first[0] + bg.dims[0] - 1 < w[0] || first[1] > w[3] || first[1] + bg.dims[1] - 1 < w[2]) continue;
                }
                std::vector<std::byte> bytes;
                store_->read_brick(i, bytes);
                layer_.emplace_back(i, std::move(bytes));
            }
        current_ = layer;
    }

    std::unique_ptr<BrickStore> store_;
    std::string name_;
    std::map<std::array<std::uint32_t, 3>, std::size_t> by_coord_;
    std::uint32_t current_ = ~0u;
    std::optional<std::array<std::int64_t, 4>> window_;  ///< x0, x1, y0, y1 (restrict_xy)
    std::vector<std::pair<std::size_t, std::vector<std::byte>>> layer_;
};

}  // namespace

std::unique_ptr<SliceSource> open_brick_store_slices(const std::string& path) {
    return std::make_unique<BrickStoreSliceSource>(path);
}

Volume read_brick_store_volume(const std::string& path) {
    auto src = open_brick_store_slices(path);
    Volume v(src->grid(), src->type());
    src->read_slices(0, v.grid.dims[2], v.bytes.data());
    return v;
}

}  // namespace meshless
