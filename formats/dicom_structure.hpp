// The element structure of a DICOM file checked before GDCM reads it (GDCM-free): Debian's GDCM is
// built with assertions, and a truncated or malformed element aborts the process inside it, so every
// element GDCM would parse is walked here first and must fit in the file.
//
// Walked: the 128-byte preamble and "DICM"; the File Meta Information group (0002,xxxx), explicit VR
// little endian, which must hold a Transfer Syntax UID (0002,0010) and be followed by a data set; the UID selects how the data set is encoded (implicit
// VR little endian, explicit VR big endian, otherwise explicit VR little endian); then every data
// element of the data set to the end of the file: sequences (defined or undefined length) and their
// items, nested at most 32 deep, and encapsulated Pixel Data (7FE0,0010) as a sequence of fragments.
// Each element's header and value must lie within the file; an undefined length is accepted only where
// DICOM allows one (a sequence, an item, encapsulated pixel data, UN); explicit VRs must be among
// those GDCM 3.0 reads (the 64-bit OV, SV, UV and unknown codes reach an assertion in it: refused).
// Pixel Data must be a top-level element, of defined length in an uncompressed transfer syntax
// (GDCM asserts otherwise). A deflated data set (1.2.840.10008.1.2.1.99) is refused (not walked).
// Throws FormatError "PATH: ..." naming the fault and its byte offset; IoError when the file cannot be
// read. Reads element headers only (values are skipped). Thread-safety: reentrant.
// Dissertation: none (input plumbing).
#pragma once
#include <cstdint>
#include <string>

namespace meshless {

/// What the walk found that a reader needs.
struct DicomStructure {
    std::uint64_t pixel_data_value_at = 0;  ///< the file offset of the top-level Pixel Data's value (0: none)
};

DicomStructure check_dicom_structure(const std::string& path);

}  // namespace meshless
