// One DICOM file as a slice of a series: the attributes the series reader needs, and the decoded
// pixels. This header is GDCM-free; formats/dicom_gdcm.cpp implements it on GDCM (the only source
// file that includes GDCM), formats/dicom_unavailable.cpp in a build configured without GDCM
// (MESHLESS_WITH_DICOM=OFF: every call throws FormatError "PATH: this build has no DICOM reader").
//
// Attributes are read from the file's data set up to Pixel Data (the pixels are not read); text
// values (UI, LO, DS, IS, CS) are taken as the file's bytes, trailing blanks and NULs removed.
// Units: positions and spacings in mm (DICOM's patient coordinates, LPS). pixel_spacing is DICOM's
// order: [0] between rows (along the column direction, y), [1] between columns (along x).
// decode_dicom_slice writes Rows x Columns stored samples, x fastest, host byte order: 1 byte each
// for 8 bits allocated, 2 for 16; bits above Bits Stored masked off and, for signed pixels,
// sign-extended from Bits Stored. Compressed transfer syntaxes are refused (FormatError) by
// read_dicom_slice_header: GDCM's decoders assert (abort the process) on damaged streams.
// Hostile input: the file's element structure is walked before GDCM parses it (formats/dicom_structure.hpp:
// Debian's GDCM aborts on a malformed element); Pixel Data's value length is read (12 bytes) where GDCM stopped, and refused when the
// file does not hold it, so GDCM never allocates for a length the file cannot back; before GDCM
// decodes, the pixel bytes the header claims are proven against the file: an uncompressed Pixel Data
// element must hold Rows x Columns x bytes (the compressed bound, kDicomMaxCompression times the
// file's size, stays for when compressed syntaxes are decoded again); the image attributes' VRs are
// checked against the dictionary before GDCM's readers take them.
// Throws IoError (cannot open), FormatError (not DICOM, unreadable data set, missing Pixel Data,
// decoding failed, decoded size not the header's); messages are one line starting with the path,
// bytes quoted from the file escaped (escape_field). Thread-safety: reentrant (GDCM's trace output
// is switched off once, process-wide). Dissertation: supplies chapter 3's regular grids.
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

namespace meshless {

/// The largest expansion a compressed slice may claim over its file's size.
inline constexpr std::uint64_t kDicomMaxCompression = 1032;

struct DicomSliceHeader {
    std::string file;                       ///< the path it was read from
    std::string sop_class_uid;              ///< (0008,0016)
    std::string series_uid;                 ///< (0020,000E) Series Instance UID
    std::string series_description;         ///< (0008,103E), may be empty
    std::string transfer_syntax;            ///< (0002,0010) UID
    bool compressed = false;                ///< an encapsulated (compressed) transfer syntax
    bool has_pixel_data = false;            ///< (7FE0,0010) present
    std::int64_t rows = 0, columns = 0;     ///< (0028,0010), (0028,0011)
    int bits_allocated = 0;                 ///< (0028,0100)
    int bits_stored = 0;                    ///< (0028,0101)
    int pixel_representation = 0;           ///< (0028,0103): 0 unsigned, 1 signed
    int samples_per_pixel = 1;              ///< (0028,0002)
    std::int64_t frames = 1;                ///< (0028,0008) Number of Frames, 1 when absent
    std::string photometric;                ///< (0028,0004)
    std::optional<std::array<double, 3>> position;     ///< (0020,0032) Image Position (Patient), mm
    std::optional<std::array<double, 6>> orientation;  ///< (0020,0037) row then column direction cosines
    std::optional<std::array<double, 2>> pixel_spacing;  ///< (0028,0030) row spacing, column spacing, mm
    double slope = 1.0, intercept = 0.0;    ///< (0028,1053), (0028,1052)
    std::string modality;                   ///< (0008,0060), e.g. "CT", "MR"; may be empty
    std::string rescale_type;               ///< (0028,1054) Rescale Type, e.g. "HU"; may be empty
    std::uint64_t file_size = 0;            ///< bytes
    /// Pixel Data's value length as the element says it (checked against the bytes after it);
    /// nullopt for an encapsulated (undefined-length) element or none.
    std::optional<std::uint64_t> pixel_data_length;

    /// Bytes per stored sample (1 or 2); 0 for pixel data this reader does not take.
    int stored_bytes() const { return bits_allocated == 8 ? 1 : bits_allocated == 16 ? 2 : 0; }
};

/// True when the build has the DICOM reader (GDCM).
bool dicom_reader_available();
/// The file starts with a 128-byte preamble and "DICM" (reads 132 bytes; false when unreadable).
bool has_dicom_magic(const std::string& path);
/// The attributes above (not the pixels). Throws as described in the file comment.
DicomSliceHeader read_dicom_slice_header(const std::string& path);
/// Decodes the one frame of `h.file` into `out` (h.rows * h.columns * h.stored_bytes() bytes).
/// Refuses pixel data other than one sample of 8 or 16 bits per pixel (FormatError), and a decoded
/// image whose size or format differs from `h`.
void decode_dicom_slice(const DicomSliceHeader& h, std::byte* out);

}  // namespace meshless
