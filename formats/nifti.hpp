// NIfTI-1 reader: single-file .nii and .nii.gz ("n+1"), and header/image pairs .hdr + .img
// ("ni1"; the .img may be gzipped as .img.gz).
//
// Byte order comes from sizeof_hdr: 348 as read -> little endian; 348 only when byte-swapped ->
// big endian (header and data swapped); anything else -> FormatError (NIfTI-2 is rejected).
// Datatypes: 2 uint8, 4 int16, 8 int32, 16 float32, 64 float64, 256 int8, 512 uint16, 768 uint32,
// 1024 int64, 1280 uint64 (others, e.g. complex/RGB, are rejected). dim[0] in 1..7, axes beyond
// z must have size 1. Spacing = |pixdim[1..3]| (0 -> 1); origin from sform (srow_*[3]) when
// sform_code > 0, else qoffset_* when qform_code > 0, else 0 (rotations are not represented).
// scl_slope != 0 with (slope, inter) != (1, 0): values become slope*v + inter as float32.
// Payload starts at vox_offset; .gz is inflated streaming (header, skip, payload).
// Throws IoError (cannot open), FormatError (bad header, unsupported type/dims, truncated).
// Thread-safety: reentrant. Dissertation: chapter 3 input volumes.
#pragma once
#include <string>

#include "formats/volume_reader.hpp"

namespace meshless {

/// `refs`: where a pair's .img may lie (formats/reference_policy.hpp; ReferenceRefused outside it).
/// The header, and the payload's claim against the data file's size (deflate's 1032:1 for .gz):
/// what read_nifti refuses before allocating, probe_nifti refuses with the same message.
VolumeInfo probe_nifti(const std::string& path, const ReferencePolicy& refs = {});
Volume read_nifti(const std::string& path, const ReferencePolicy& refs = {});
/// read_nifti's checks, a gzipped payload inflated through a small buffer (meshless info). Throws as read_nifti.
void prove_nifti(const std::string& path, const ReferencePolicy& refs = {});

}  // namespace meshless
