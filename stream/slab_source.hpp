// Source of paradigm (C) work over a volume streamed slab by slab (dissertation section 3.6:
// volumes need not fit in memory): reads chunks of consecutive z-slices through a SliceSource
// (ooc/slice_source.hpp: raw, NRRD, MetaImage, Voreen payloads straight from disk) and emits
// batches naming cell rows of one chunk, with the chunk attached (Batch::chunk; rows are local to
// the chunk, row r = j + (ny-1)*k as in kernels/cell_sampling.hpp). A chunk holding cell slabs
// [c0, c1) holds sample slices [c0, c1]; the shared slice is copied from the previous chunk, so
// every slice is read once. GenerateStage and GenerateProjectStage sample a chunk's rows with
// index offset z0, so the records are bit for bit those of the in-memory volume, in the same order.
// Memory: the chunks referenced by batches in flight plus one (each about `chunk_bytes`), their
// buffers recycled; never the volume. Also faster than reading the volume whole: the buffers are
// mapped once, where a whole read (or a file mapping) pays for mapping every page of the volume.
// Batch boundaries depend only on the grid and chunk_bytes, never on the thread count.
// Not thread-safe (the runner calls next() serially); chunks are immutable once emitted and may be
// released from any thread. Throws what the SliceSource throws.
#pragma once
#include <cstddef>
#include <memory>

#include "ooc/slice_source.hpp"
#include "stream/stage.hpp"

namespace meshless {

class SlabSource final : public Source {
public:
    Payload gives() const override { return Payload::cells; }
    /// The slice source must outlive this source. chunk_bytes: target size of one chunk (at least
    /// two slices are read whatever it says).
    explicit SlabSource(SliceSource& slices, std::size_t chunk_bytes = std::size_t{2} << 20);
    ~SlabSource() override;
    std::optional<Batch> next() override;
    /// Cell slabs per chunk.
    std::int64_t slabs_per_chunk() const { return slabs_per_chunk_; }

    struct Pool;  // recycled chunk buffers (internal)

private:
    void read_chunk();
    SliceSource& slices_;
    GridSpec grid_;
    std::int64_t slabs_per_chunk_ = 1, rows_per_batch_ = 1;
    std::int64_t next_slab_ = 0;     // first cell slab of the next chunk
    std::int64_t row_ = 0, rows_ = 0;  // local rows of the current chunk: next, count
    std::shared_ptr<const VolumeChunk> chunk_;
    std::shared_ptr<Pool> pool_;
    std::uint64_t seq_ = 0;
};

}  // namespace meshless
