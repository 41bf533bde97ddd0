// Sources of z-slices for the slab-streaming converter (dissertation section 3.6: volumes bigger
// than RAM): the converter pulls consecutive slices, so a source never needs the whole volume.
//   open_slice_source: raw files, and NRRD/MetaImage/Voreen headers whose payload is raw or gzip
//     (one file or a list of slab files, no line skip), stream from disk slab by slab, converted to
//     the same sample type read_volume gives; a DICOM series decodes one slice file at a time
//     (formats/dicom_series.hpp); a Zarr store decodes one z-row of chunks at a time (formats/zarr.hpp);
//     other formats are read whole and served from memory.
//   make_upsampling_source: trilinear or tricubic (Catmull-Rom, clamped at the borders) upsampling
//     of an in-memory volume by an integer factor f: dims (n-1)*f+1 (1 stays 1), spacing/f, same
//     origin and sample type (integers rounded to nearest and clamped), computed slice by slice
//     (meshless synth). Fine voxel f*i is exactly coarse voxel i.
//   make_volume_source: a volume already in memory (tests, callers that have one).
// read_slices fills `count` consecutive z-slices starting at k, samples in native type, x fastest;
// sources are read with increasing, contiguous k (raw files and memory allow any k; gzip payloads
// restart decompression when asked to go back). A range outside [0, nz) is an InvalidArgument.
// Throws FormatError/IoError naming the file; InvalidArgument for an upsampling factor outside
// 1..64 or an upsampled slice wider than 2^31 samples, and for RawOptions::array given with a
// brick store, a DICOM series or another format of one unnamed array (formats/payload.hpp). One source per thread (sources keep read state).
#pragma once
#include <cstddef>
#include <memory>
#include <string>

#include "formats/volume_reader.hpp"
#include "kernels/grid.hpp"

namespace meshless {

class SliceSource {
public:
    virtual ~SliceSource() = default;
    virtual const GridSpec& grid() const = 0;
    virtual SampleType type() const = 0;
    virtual void read_slices(std::int64_t k, std::int64_t count, std::byte* out) = 0;
    /// Human-readable name for messages (the input path).
    virtual std::string name() const = 0;
    /// Only samples with x in [x0, x1] and y in [y0, y1] will be used from now on: a source may
    /// leave the others of later slices unwritten (a brick store then reads only the bricks of that
    /// window: ooc/cropped_slice_source.hpp). The default reads every sample.
    virtual void restrict_xy(std::int64_t x0, std::int64_t x1, std::int64_t y0, std::int64_t y1) {
        (void)x0, (void)x1, (void)y0, (void)y1;
    }
};

std::unique_ptr<SliceSource> open_slice_source(const std::string& path, const RawOptions& raw = {});

/// Serves slices of a volume held in memory (taken over by the source).
std::unique_ptr<SliceSource> make_volume_source(Volume v, std::string name);

enum class Upsampling { trilinear, tricubic };
/// The volume must outlive the source.
std::unique_ptr<SliceSource> make_upsampling_source(const Volume& v, int factor, Upsampling mode,
                                                    std::string name);

}  // namespace meshless
