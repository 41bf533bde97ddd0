// The min/max of 32-cell blocks of a volume read slab by slab or split across threads, for the
// framing of the chapter-3 pictures and the value range (dissertation section 3.6: the surface's
// bounds known before extraction). The blocks are those of kernels/block_minmax.hpp, aligned as the
// bricks of a store with edge `edge`; every function here gives the same blocks as block_minmax of
// the whole volume in memory, whatever the thread count. Memory: about 1 MiB of slices a reader.
// Throws what the slice sources throw (FormatError, IoError naming the file).
#pragma once
#include <cstddef>
#include <functional>
#include <memory>

#include "kernels/block_minmax.hpp"
#include "ooc/slice_source.hpp"

namespace meshless {

/// block_minmax over a slab-streamed volume: about 1 MiB of slices at a time (every slice read
/// once, in order, into one reused buffer), so the pass costs neither memory nor page faults.
BlockMinMax streamed_block_minmax(SliceSource& s, int edge);

/// The same, the layers of blocks computed in parallel on `threads` threads (the one parallel
/// helper of volume inputs: it runs in a task arena of its own, as the runner does,
/// stream/runner.hpp), each thread reading its layers through its own reader from `reopen` (a raw
/// payload, read at any k) in pieces of about 1 MiB, or, when `data` is not null, straight from the
/// volume in memory at `data` (grid g, samples of `type`, x fastest). Layers are joined in z order.
BlockMinMax parallel_block_minmax(const GridSpec& g, SampleType type, int edge, int threads,
                                  const std::function<std::unique_ptr<SliceSource>()>& reopen, const std::byte* data);

}  // namespace meshless
