// MetaImage reader (ITK/VTK MetaIO): .mhd header with a separate data file, or .mha with
// "ElementDataFile = LOCAL" (data follows the header line).
//
// Keys: NDims (2..4, extra axes of size 1), DimSize, ElementSpacing (else ElementSize), Offset /
// Position / Origin, ElementType (MET_UCHAR, MET_CHAR, MET_USHORT, MET_SHORT, MET_UINT, MET_INT,
// MET_ULONG, MET_LONG (4 bytes), MET_ULONG_LONG, MET_LONG_LONG, MET_FLOAT, MET_DOUBLE),
// ElementByteOrderMSB / BinaryDataByteOrderMSB, ElementNumberOfChannels (must be 1),
// CompressedData (zlib), BinaryData = False (ascii), HeaderSize (-1 = data at end of file),
// ElementDataFile: LOCAL | name | LIST | "fmt min max step".
// Throws IoError (cannot open), FormatError (bad/unsupported keys, size mismatch).
// Thread-safety: reentrant. Dissertation: chapter 3 input volumes.
#pragma once
#include <string>

#include "formats/payload.hpp"

namespace meshless {

PayloadPlan plan_metaimage(const std::string& path);
VolumeInfo probe_metaimage(const std::string& path);
Volume read_metaimage(const std::string& path);

}  // namespace meshless
