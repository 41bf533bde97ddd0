#include "stream/volume_block_minmax.hpp"

#include <algorithm>
#include <vector>

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/enumerable_thread_specific.h>
#include <oneapi/tbb/global_control.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/task_arena.h>

#include "kernels/grid.hpp"

namespace meshless {

namespace {

/// Appends one layer of blocks (edge + 1 slices or fewer, one block deep) to `all`.
void append_layer(BlockMinMax& all, const BlockMinMax& layer) {
    all.blocks = {layer.blocks[0], layer.blocks[1], all.blocks[2] + 1};
    all.vmin.insert(all.vmin.end(), layer.vmin.begin(), layer.vmin.end());
    all.vmax.insert(all.vmax.end(), layer.vmax.begin(), layer.vmax.end());
}

/// Layer i of blocks holds slices [i * edge, min(i * edge + edge, nz - 1)].
std::int64_t block_layers(const GridSpec& g, int edge) {
    return std::max<std::int64_t>(1, (g.dims[2] - 1 + edge - 1) / edge);
}

}  // namespace

BlockMinMax streamed_block_minmax(SliceSource& s, int edge) {
    const GridSpec g = s.grid();
    BlockMinMaxBuilder b(g, s.type(), edge);
    const auto slice_bytes = static_cast<std::size_t>(g.dims[0] * g.dims[1]) * sample_size(s.type());
    if (slice_bytes == 0) return std::move(b).finish();
    const std::int64_t step = std::max<std::int64_t>(1, static_cast<std::int64_t>((std::size_t{1} << 20) / slice_bytes));
    const std::unique_ptr<std::byte[]> buf(new std::byte[slice_bytes * static_cast<std::size_t>(step)]);
    for (std::int64_t k = 0; k < g.dims[2]; k += step) {
        const std::int64_t n = std::min(step, g.dims[2] - k);
        s.read_slices(k, n, buf.get());
        b.add_slices(k, n, buf.get());
    }
    return std::move(b).finish();
}

BlockMinMax parallel_block_minmax(const GridSpec& g, SampleType type, int edge, int threads,
                                  const std::function<std::unique_ptr<SliceSource>()>& reopen, const std::byte* data) {
    const auto slice_bytes = static_cast<std::size_t>(g.dims[0] * g.dims[1]) * sample_size(type);
    const std::int64_t nlayers = block_layers(g, edge);
    const std::int64_t step = std::max<std::int64_t>(1, static_cast<std::int64_t>((std::size_t{1} << 20) / std::max<std::size_t>(slice_bytes, 1)));
    std::vector<BlockMinMax> layers(static_cast<std::size_t>(nlayers));
    struct Reader {
        std::unique_ptr<SliceSource> src;
        std::unique_ptr<std::byte[]> buf;
    };
    oneapi::tbb::enumerable_thread_specific<Reader> readers;
    auto one = [&](std::int64_t i) {
        const std::int64_t z0 = i * edge, n = std::min<std::int64_t>(z0 + edge, g.dims[2] - 1) - z0 + 1;
        GridSpec part = g;
        part.dims[2] = n;
        if (data) {
            layers[static_cast<std::size_t>(i)] =
                block_minmax(VolumeView{data + slice_bytes * static_cast<std::size_t>(z0), type, part}, edge);
            return;
        }
        Reader& r = readers.local();
        if (!r.src) r.src = reopen();
        if (!r.buf) r.buf.reset(new std::byte[slice_bytes * static_cast<std::size_t>(step)]);
        BlockMinMaxBuilder b(part, type, edge);
        for (std::int64_t k = 0; k < n; k += step) {
            const std::int64_t m = std::min(step, n - k);
            r.src->read_slices(z0 + k, m, r.buf.get());
            b.add_slices(k, m, r.buf.get());
        }
        layers[static_cast<std::size_t>(i)] = std::move(b).finish();
    };
    // as many threads as asked for, even beyond the core count (as the runner, stream/runner.cpp)
    oneapi::tbb::global_control allow(oneapi::tbb::global_control::max_allowed_parallelism,
                                      static_cast<std::size_t>(threads));
    oneapi::tbb::task_arena arena(threads);
    arena.execute([&] {
        oneapi::tbb::parallel_for(oneapi::tbb::blocked_range<std::int64_t>(0, nlayers, 1),
                                  [&](const oneapi::tbb::blocked_range<std::int64_t>& r) {
                                      for (std::int64_t i = r.begin(); i != r.end(); ++i) one(i);
                                  });
    });
    BlockMinMax all;
    all.edge = edge;
    for (const BlockMinMax& layer : layers) append_layer(all, layer);
    return all;
}

}  // namespace meshless
