#include "ooc/cropped_slice_source.hpp"

#include <cstring>
#include <vector>

#include "kernels/errors.hpp"
#include "kernels/volume_crop.hpp"

namespace meshless {

namespace {

class CroppedSliceSource final : public SliceSource {
public:
    CroppedSliceSource(std::unique_ptr<SliceSource> s, const VoxelBox& box)
        : source_(std::move(s)), box_(box), grid_(cropped_grid(source_->grid(), box)) {
        source_->restrict_xy(box.lo[0], box.hi[0], box.lo[1], box.hi[1]);
    }
    const GridSpec& grid() const override { return grid_; }
    SampleType type() const override { return source_->type(); }
    std::string name() const override { return source_->name(); }
    void read_slices(std::int64_t k, std::int64_t count, std::byte* out) override {
        if (k < 0 || count < 0 || k + count > grid_.dims[2])
            throw InvalidArgument(name() + ": cropped slices " + std::to_string(k) + " + " + std::to_string(count) + " outside 0.." +
                                  std::to_string(grid_.dims[2]));
        const GridSpec& g = source_->grid();
        const std::size_t ss = sample_size(type());
        const std::size_t slice = static_cast<std::size_t>(g.dims[0] * g.dims[1]) * ss;
        const std::size_t row = static_cast<std::size_t>(grid_.dims[0]) * ss;
        whole_.resize(slice * static_cast<std::size_t>(count));
        source_->read_slices(box_.lo[2] + k, count, whole_.data());
        for (std::int64_t s = 0; s < count; ++s)
            for (std::int64_t j = 0; j < grid_.dims[1]; ++j)
                std::memcpy(out + (static_cast<std::size_t>(s * grid_.dims[1] + j)) * row,
                            whole_.data() + static_cast<std::size_t>(s) * slice +
                                static_cast<std::size_t>((box_.lo[1] + j) * g.dims[0] + box_.lo[0]) * ss,
                            row);
    }

private:
    std::unique_ptr<SliceSource> source_;
    VoxelBox box_;
    GridSpec grid_;
    std::vector<std::byte> whole_;  // the source's slices of the last request
};

}  // namespace

std::unique_ptr<SliceSource> make_cropped_source(std::unique_ptr<SliceSource> source, const VoxelBox& box) {
    return std::make_unique<CroppedSliceSource>(std::move(source), box);
}

}  // namespace meshless
