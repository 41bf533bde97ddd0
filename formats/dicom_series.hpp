// A DICOM series as one regular volume: the files of an input gathered, grouped by Series Instance
// UID, one series chosen, its slices sorted along the orientation normal and checked to form a
// regular grid (dissertation chapter 3's input volumes, from CT archives).
//
// Inputs: a folder (its regular files whose bytes 128..131 are "DICM"; other files, hidden files
// and a DICOMDIR are skipped; not recursive), a DICOMDIR file (every DICOM file under its folder,
// recursively: the files its records name lie there), or one DICOM file (the series it belongs to,
// among the files of its folder).
// Series: grouped by Series Instance UID (0020,000E) and listed in the order of their UIDs. With
// more than one image series the input is refused (FormatError) with one line listing them
// (number, UID, description, slice count, Columns x Rows), unless `choice` names one: its UID, or
// its number N (1-based) in that list (InvalidArgument when it names none).
// Geometry: slices are sorted by Image Position (Patient) (0020,0032) projected on the normal of
// Image Orientation (Patient) (0020,0037), row x column direction: never by file name or instance
// number. x runs along the row direction (Columns samples, Pixel Spacing[1] apart), y along the
// column direction (Rows, Pixel Spacing[0]), z along the normal; the z spacing is the first-to-last
// distance over N-1 (Spacing Between Slices is not used). Positions are LPS millimetres. When the
// three axes run along the patient axes (formats/anatomical_frame.hpp axis_aligned_signs: axial,
// coronal or sagittal series without permutation), the volume is in world coordinates: the origin
// is the first slice's position and an axis running backwards is reversed (origin at its last
// sample), as the NRRD and NIfTI readers do; otherwise (oblique) positions are index x spacing from
// the first slice's position. The patient axes are recorded in `frame` (source "Image Orientation
// (Patient)").
// Samples: Rescale Slope (0028,1053) and Intercept (0028,1052) applied per slice: float32 when any
// slice's pair is not (1, 0), else the stored type (8-bit unsigned uint8, 8-bit signed int16,
// 16-bit uint16 or int16).
// Refused (FormatError, one line starting with the input's path, naming the file(s) and what is
// wrong, bytes from files escaped): no DICOM files, a series without pixel data, unsupported pixel
// data (several samples per pixel, not 8 or 16 bits, several frames), mixed sizes, pixel formats,
// pixel spacings or orientations, missing Image Position/Orientation (more than one slice),
// gantry tilt (positions off the normal by more than 1e-3 of their distance, the angle said),
// duplicated slices (two at one position), missing slices (a step a whole multiple of the usual
// one) and uneven spacing (a step more than 1% from the median; the steps said), a rescale whose
// values leave the float32 range, and Rows x Columns x slices against the files' sizes (an
// uncompressed slice must hold its pixels; a compressed one at most kDicomMaxCompression:1).
// Memory: the headers (no pixels) while opening; read_dicom_series_slice decodes one file at a time.
// Thread-safety: reentrant; a DicomSeries is read-only once opened.
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "formats/anatomical_frame.hpp"
#include "formats/dicom_slice.hpp"
#include "formats/reference_policy.hpp"
#include "kernels/grid.hpp"

namespace meshless {

struct DicomSeriesSummary {
    std::string uid, description;  ///< as in the files (not escaped)
    std::int64_t slices = 0;
    std::int64_t columns = 0, rows = 0;  ///< of its first file
};

struct DicomSeries {
    std::string input;                        ///< the path given
    GridSpec grid;                            ///< dims {Columns, Rows, slices}
    SampleType type = SampleType::u8;
    std::optional<AnatomicalFrame> frame;
    std::vector<DicomSliceHeader> slices;     ///< sorted along the normal (file order, before any z reversal)
    std::array<bool, 3> flip{false, false, false};  ///< axes reversed to world order (x, y within a slice; z: slices)
    bool rescaled = false;                    ///< samples are slope x stored + intercept (type float32)
    std::string uid, description;             ///< the chosen series
    /// The unit of the (rescaled) values: the first slice's Rescale Type (0028,1054) unless "US"
    /// (unspecified), else "HU" for a CT (PS3.3 C.11.1.1.2: CT values rescale to Hounsfield units), else "".
    std::string value_unit;
    std::vector<DicomSeriesSummary> series;   ///< every image series of the input, in listing order
};

/// The input is a DICOM folder, DICOMDIR or file: a file with the DICM magic or named DICOMDIR, a
/// folder with such a file among its first `scan` entries. Never throws.
bool looks_like_dicom(const std::string& path, std::size_t scan = 64);

/// Gathers, groups, chooses and checks as the file comment says (headers only). `refs` confines
/// every file read (ReferenceRefused).
DicomSeries open_dicom_series(const std::string& path, const std::string& choice = {}, const ReferencePolicy& refs = {});

/// The image series of the input, in listing order (headers only; no series is checked). Throws as
/// open_dicom_series for the input itself (no DICOM files, no image series, unreadable headers).
std::vector<DicomSeriesSummary> list_dicom_series(const std::string& path, const ReferencePolicy& refs = {});

/// Volume slice k (0 <= k < dims[2]) into `out`: Columns x Rows samples of s.type, x fastest.
/// `scratch` is a reused buffer for the decoded file. Throws as decode_dicom_slice.
void read_dicom_series_slice(const DicomSeries& s, std::int64_t k, std::byte* out, std::vector<std::byte>& scratch);

/// The whole series, slice by slice, into one Volume (allocated after open_dicom_series proved it).
Volume read_dicom_series(const DicomSeries& s);

/// "1.2.3 'CT HEAD', 200 slices, 64 x 64" for messages and `info` (UID and description escaped).
std::string describe_dicom_series(const DicomSeriesSummary& s);

}  // namespace meshless
