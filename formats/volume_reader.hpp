// Regular-volume readers: one entry point that dispatches on extension (and content) to the
// per-format readers (raw, NRRD, MetaImage, VTK legacy, VTK XML .vti, vtk-js index.json, SLC,
// NIfTI-1, Voreen .dat, DICOM series: a folder, DICOMDIR or slice file, formats/dicom_series.hpp;
// NumPy .npy 3-D arrays, formats/npy_volume.hpp; Zarr v2 stores and OME-Zarr images, formats/zarr.hpp).
//
// Output: a Volume with samples x fastest, then y, then z, in host (little-endian) order.
// Types: uint8, int16, uint16, float32 are kept; int8 widens to int16; int32/uint32/int64/
// uint64/float64 convert to float32 (integers above 2^24 round). Units: spacing/origin in the
// file's world units (voxels when the file gives none). A negative spacing (NRRD spacings, MetaImage,
// VTK legacy, VTI, vtk.js) is honoured as a reversed axis: the samples are reversed and the origin
// moved to the last sample, so every world position keeps its value (kernels/flip_axes.hpp).
// Hostile headers: sizes are checked (kernels/checked_size.hpp), the grid validated
// (validate_grid: NaN/infinite/zero spacing and NaN origins refused) and a payload's size proven
// against its file before anything is allocated; compressed payloads are bounded by their coding's
// largest expansion and decoded into lazily committed pages.
// Arrays: VTK XML .vti, VTK legacy .vtk and vtk.js images may hold several point arrays;
// RawOptions::array names the one to read (default: the active scalars where the file names them,
// else the first). A name the file lacks is a FormatError listing the arrays it has; a name given
// for a format of one unnamed array (every other format, a brick store too) is an InvalidArgument.
// References: a detached header's data files are followed wherever the format allows (absolute
// paths, `..`), unless RawOptions::references confines them (ReferenceRefused, a FormatError).
// Throws: IoError (cannot open, is a directory, missing data file), FormatError (bad or
// unsupported content: magic, version, encoding, type, sizes, truncation), InvalidArgument (raw
// options out of range, see raw_volume.hpp; RawOptions::array for a format of one unnamed array); messages are one
// line starting with the offending path. Thread-safety: reentrant; no shared state.
// Dissertation: supplies the regular grids of chapter 3 (iso-splatting of volume data).
#pragma once
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "formats/anatomical_frame.hpp"
#include "formats/reference_policy.hpp"
#include "kernels/grid.hpp"

namespace meshless {

/// Layout of headerless raw files. Fields given here override what the file name convention
/// (`name_XxYxZ_type.raw`) or a sibling Voreen `.dat` says. `type` is the Volume type to read
/// as (stored type = that type); other stored types need a header (.dat/.nhdr/.mhd).
/// `references` applies to every format: where the input and the files its header names may lie
/// (formats/reference_policy.hpp; default unconfined). A confined reader checks the input and each
/// referenced file before opening it and throws ReferenceRefused for one outside the root.
struct RawOptions {
    std::optional<std::array<std::int64_t, 3>> dims;
    std::optional<SampleType> type;
    bool big_endian = false;
    std::optional<std::array<double, 3>> spacing;
    ReferencePolicy references;
    /// DICOM: the series to read from an input holding several, by Series Instance UID or by its
    /// 1-based number in the input's listing (empty: the only one; formats/dicom_series.hpp).
    std::string series;
    /// VTK XML .vti, VTK legacy .vtk, vtk.js: the point array to read, by its name in the file (empty:
    /// the default, the active scalars where the file names them, else the first array). The readers
    /// of formats with one unnamed array throw InvalidArgument when it is set (formats/payload.hpp
    /// refuse_array_choice).
    std::string array;
    /// OME-Zarr images: the multiscale level to read (0: the full resolution; formats/zarr.hpp).
    /// Other formats hold one resolution: their readers throw InvalidArgument when it is not 0.
    int resolution_level = 0;
};

/// Reads a whole volume. Dispatch: .raw .npy .nrrd .nhdr .mhd .mha .vtk .vti (file: VTK XML,
/// directory: vtk-js) .json (vtk-js index) .slc .nii .nii.gz .hdr .dat, a directory holding
/// index.json, a Zarr v2 store (a folder with .zarray, an OME-Zarr folder with .zattrs multiscales, a
/// folder named *.zarr, or the .zarray itself: formats/zarr.hpp), a DICOM folder, DICOMDIR or slice
/// file ("DICM" at byte 128), else by content (magic).
Volume read_volume(const std::string& path, const RawOptions& raw = {});

/// The same volume as read_volume, read the fastest way for one pass over it: when the samples are
/// one uncompressed file in host byte order and a native type (raw, .npy, NRRD, MetaImage, Voreen .dat
/// with raw encoding), the Volume maps the file (formats/mapped_file.hpp: no read, no copy; the
/// file must not be truncated while the Volume lives); every other case is read_volume.
Volume map_volume(const std::string& path, const RawOptions& raw = {});

/// One point array of a volume file that may hold several (VTK XML .vti, VTK legacy .vtk, vtk.js).
struct VolumeArray {
    std::string name;            ///< as the file spells it (escape it before printing)
    std::string type;            ///< its stored type (formats/stored_type.hpp: "uint8", "int32", "float64", ...), else the file's type name (escaped)
    std::int64_t components = 1; ///< values per point (0: unreadable); only 1 can be read as a volume
};

struct VolumeInfo {
    std::string format;                   ///< "raw", "npy", "nrrd", "metaimage", "vtk-legacy", "vti", "vtkjs", "slc", "nifti", "voreen-dat", "dicom", "zarr", "ome-zarr"
    GridSpec grid;
    SampleType type = SampleType::u8;     ///< the type read_volume returns
    std::string encoding;                 ///< "raw", "gzip", "ascii", "rle", "base64", "base64+zlib", "appended-raw", ...
    std::vector<std::string> data_files;  ///< files holding the payload (the path itself when attached)
    bool maps = false;                    ///< map_volume maps the file: the samples cost no memory of their own
    std::optional<AnatomicalFrame> frame; ///< the patient's axes, where the header says them (formats/anatomical_frame.hpp)
    std::string length_unit;              ///< the world coordinates' unit where the file says it (formats/length_unit.hpp), else ""
    std::string value_unit;               ///< the values' unit where the file says it (DICOM Rescale Type or HU for CT, NRRD
                                          ///< sample units; as written, escaped, at most 16 bytes), else ""
    std::string series;                   ///< DICOM: the series read and the others of the input (escaped), else empty
    std::vector<VolumeArray> arrays;      ///< .vti, .vtk, vtk.js: the point arrays in file order (a legacy file's up to
                                          ///< its CELL_DATA), else empty
    std::size_t default_array = 0;        ///< the index in `arrays` read without RawOptions::array
    std::size_t read_array = 0;           ///< the index in `arrays` read (RawOptions::array, else default_array)
};

/// Parses headers only (no payload read, no decompression beyond a NIfTI .gz header).
VolumeInfo probe_volume(const std::string& path, const RawOptions& raw = {});

/// probe_volume, then proves the payload as the readers would before allocating it, and decodes it
/// without keeping it (what `meshless info` runs): sizes against the files (check_payload_plan),
/// deflate's 1032:1 and SLC run-length bounds, then gzip/zlib streams inflated through a small
/// buffer (one VTI block at a time), SLC slices decoded into one reused plane, ascii values parsed.
/// A bomb, a truncated or corrupt payload throws here exactly as read_volume would. Memory: a small
/// buffer, except the document of a VTI or SLC file (read whole, as their readers do) and ascii text.
/// Its VolumeInfo::arrays of a VTK legacy file lists every point array (probe_volume's stops at the
/// array read: the values of the others are not skipped).
VolumeInfo prove_volume(const std::string& path, const RawOptions& raw = {});

/// The bytes the samples of `vi` take once decoded into memory (voxels x sample size, checked).
std::uint64_t decoded_bytes(const VolumeInfo& vi, const std::string& path);

/// By extension: .raw .nrrd .nhdr .mhd .mha .vtk .vti .slc .nii .nii.gz .dat, a .npy of 3 dimensions, a .json that is
/// a vtk-js index, a directory holding index.json; a Zarr store (formats/zarr.hpp looks_like_zarr); a DICOM file, DICOMDIR or a folder with a DICOM
/// file among its first 64 entries (formats/dicom_series.hpp looks_like_dicom). Does not open the payload.
bool looks_like_volume(const std::string& path);

/// read_volume would read `path` as a DICOM series (formats/dicom_series.hpp): streaming readers
/// (ooc/slice_source.hpp) read it slice by slice. Reads no more than the detection does; never throws.
bool is_dicom_input(const std::string& path, const RawOptions& raw = {});

}  // namespace meshless
