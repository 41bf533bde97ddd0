// A NumPy volume served slice by slice to the slab-streaming iso-splatting graph
// (ooc/slice_source.hpp, stream/isosplat_pipeline.hpp run_isosplat_slabs: the same bytes as the
// whole-volume graph). For an np.memmap of a file mapped shared (modes r, r+, w+), the pages of the
// slices already served are handed back to the kernel (madvise MADV_DONTNEED: a shared file
// mapping loses nothing, a later access reads the file again), so the call's resident memory stays
// a few slabs however large the mapped volume: bigger-than-RAM volumes from Python. Never used on
// other memory (DONTNEED would zero anonymous or copy-on-write pages). Reads must go forward
// (SlabSource does); throws InvalidArgument for a slice range outside the volume.
#pragma once
#include <string>

#include "kernels/grid.hpp"
#include "ooc/slice_source.hpp"

namespace meshless::python {

class ArraySlices final : public SliceSource {
public:
    /// view: contiguous, x fastest (volume_view's); release_pages: only for shared file mappings.
    ArraySlices(const VolumeView& view, bool release_pages);
    const GridSpec& grid() const override { return view_.grid; }
    SampleType type() const override { return view_.type; }
    void read_slices(std::int64_t k, std::int64_t count, std::byte* out) override;
    std::string name() const override { return "volume"; }

private:
    VolumeView view_;
    bool release_;
    std::size_t slice_bytes_;
    const std::byte* released_;  ///< pages below this were handed back
};

}  // namespace meshless::python
