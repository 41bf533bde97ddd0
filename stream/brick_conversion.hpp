// The brick-store conversion recipe, what `meshless convert VOLUME -o vol.mlb` and `meshless synth`
// run (and any other front end): the volume opened as a slice source (a file streamed slab by slab,
// standard input spooled, or an upsampled volume), the patient's axes its header gives, and the
// one-line report of --stats (docs/architecture.md "Brick store"; dissertation section 3.6).
// The conversion itself is ooc/brick_converter.hpp's convert_to_brick_store, run by the caller on
// the source so that it can size its progress line on the source's slices.
// Units: world coordinates; bytes; seconds (MB = 10^6 bytes in the report).
// Throws FormatError for bad data, IoError for files that cannot be read (naming the file,
// "- (stdin)" for standard input), as stream/volume_input.hpp does.
#pragma once
#include <array>
#include <memory>
#include <optional>
#include <string>

#include "ooc/brick_converter.hpp"
#include "ooc/slice_source.hpp"
#include "stream/volume_input.hpp"

namespace meshless {

/// What a volume file's header says that a store records for its pictures: the patient axes
/// (formats/anatomical_frame.hpp; pictures of the store then face as pictures of the volume do) and
/// the length unit (formats/length_unit.hpp; the scale bar's label).
struct VolumeLabels {
    std::optional<std::array<std::array<double, 3>, 3>> patient_axes;
    std::string length_unit;
    std::string value_unit;  ///< the values' unit (formats/length_unit.hpp value_unit_text): the legend's
};
/// The labels of `path`; a brick store gives those it recorded. None when the header cannot be
/// probed: they only label pictures, and the conversion itself reports what is wrong with the input.
VolumeLabels volume_labels_of(const std::string& path, const RawOptions& raw);

/// A volume ready to be converted: its slices and the labels to record (ConvertParams::patient_axes,
/// ConvertParams::length_unit).
struct ConversionInput {
    std::unique_ptr<const Volume> volume;  ///< the volume `slices` reads, when it reads one held here
    std::unique_ptr<SliceSource> slices;
    VolumeLabels labels;
};

/// Opens `path` for conversion: a file through open_slice_source (streamed when its format allows,
/// read whole otherwise) with o.raw; "-" (standard input) spooled through open_volume_input with
/// `o` (o.stream set: streamed when it can be).
ConversionInput open_conversion_input(const std::string& path, const VolumeOpenOptions& o);

/// The volume at `path` read whole (load_volume with `o`), upsampled by `factor` with `mode` slice by
/// slice (make_upsampling_source); the axes of the file ("-": none), which upsampling keeps.
ConversionInput open_upsampled_input(const std::string& path, const VolumeOpenOptions& o, int factor, Upsampling mode);

/// The --stats line (no newline): "COMMAND: XxYxZ TYPE -> OUT: N bricks of B cells, level L, ...
/// MB in S s (MB/s), MB stored, ratio R".
std::string brick_conversion_report(const std::string& command, const SliceSource& src, const std::string& out,
                                    const ConvertParams& p, const ConvertStats& st);

}  // namespace meshless
