#include "stream/slab_source.hpp"

#include <algorithm>
#include <cstring>
#include <mutex>
#include <vector>

#include "kernels/cell_sampling.hpp"

namespace meshless {

struct SlabSource::Pool {
    std::mutex m;
    std::vector<SampleBytes> free;
    static constexpr std::size_t kCap = 64;
};

namespace {

/// Returns a chunk's buffer to the pool when the last batch referencing it is done.
struct ChunkReturn {
    std::shared_ptr<SlabSource::Pool> pool;
    void operator()(VolumeChunk* c) const {
        {
            std::lock_guard lock(pool->m);
            if (pool->free.size() < SlabSource::Pool::kCap) pool->free.push_back(std::move(c->samples.bytes));
        }
        std::default_delete<VolumeChunk>()(c);
    }
};

}  // namespace

SlabSource::SlabSource(SliceSource& slices, std::size_t chunk_bytes)
    : slices_(slices), grid_(slices.grid()), pool_(std::make_shared<Pool>()) {
    const std::int64_t nx = grid_.dims[0], ny = grid_.dims[1];
    const auto slice_bytes = static_cast<std::size_t>(nx * ny) * sample_size(slices.type());
    slabs_per_chunk_ = std::max<std::int64_t>(1, static_cast<std::int64_t>(chunk_bytes / std::max<std::size_t>(1, slice_bytes)) - 1);
    rows_per_batch_ = std::max<std::int64_t>(1, static_cast<std::int64_t>(kMaxBatchRecords) / std::max<std::int64_t>(1, nx - 1));
}

SlabSource::~SlabSource() = default;

void SlabSource::read_chunk() {
    const std::int64_t cell_slabs = cell_row_count(grid_) == 0 ? 0 : grid_.dims[2] - 1;
    const std::int64_t c0 = next_slab_, c1 = std::min(cell_slabs, c0 + slabs_per_chunk_);
    const std::int64_t slices = c1 - c0 + 1;
    GridSpec g = grid_;
    g.dims[2] = slices;
    const SampleType type = slices_.type();
    const auto slice_bytes = static_cast<std::size_t>(g.dims[0] * g.dims[1]) * sample_size(type);
    SampleBytes bytes;
    {
        std::lock_guard lock(pool_->m);
        if (!pool_->free.empty()) {
            bytes = std::move(pool_->free.back());
            pool_->free.pop_back();
        }
    }
    bytes.resize(slice_bytes * static_cast<std::size_t>(slices));
    std::int64_t first = 0;  // slices already in place
    if (chunk_ && chunk_->z0 + chunk_->samples.grid.dims[2] - 1 == c0) {
        std::memcpy(bytes.data(), chunk_->samples.bytes.data() + slice_bytes * static_cast<std::size_t>(chunk_->samples.grid.dims[2] - 1),
                    slice_bytes);
        first = 1;
    }
    slices_.read_slices(c0 + first, slices - first, bytes.data() + slice_bytes * static_cast<std::size_t>(first));
    auto c = std::make_unique<VolumeChunk>();
    c->samples.grid = g;
    c->samples.type = type;
    c->samples.bytes = std::move(bytes);
    c->z0 = c0;
    chunk_ = std::shared_ptr<const VolumeChunk>(c.release(), ChunkReturn{pool_});
    next_slab_ = c1;
    row_ = 0;
    rows_ = cell_row_count(g);
}

std::optional<Batch> SlabSource::next() {
    if (row_ >= rows_) {
        const std::int64_t cell_slabs = cell_row_count(grid_) == 0 ? 0 : grid_.dims[2] - 1;
        if (next_slab_ >= cell_slabs) {
            chunk_.reset();
            return std::nullopt;
        }
        read_chunk();
    }
    Batch b;
    b.seq = seq_++;
    b.kind = RecordKind::sample;
    b.cells.k0 = row_;
    b.cells.k1 = std::min(rows_, row_ + rows_per_batch_);
    b.chunk = chunk_;
    row_ = b.cells.k1;
    return b;
}

}  // namespace meshless
