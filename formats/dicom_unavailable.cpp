// formats/dicom_slice.hpp in a build configured without GDCM (MESHLESS_WITH_DICOM=OFF): a DICOM
// input is refused in one line saying so. CMake compiles this file instead of dicom_gdcm.cpp.
#include "formats/dicom_slice.hpp"

#include "kernels/errors.hpp"

namespace meshless {

namespace {
[[noreturn]] void no_reader(const std::string& path) {
    throw FormatError(path + ": this build has no DICOM reader (configured without GDCM: install libgdcm-dev and "
                             "configure with -DMESHLESS_WITH_DICOM=ON)");
}
}  // namespace

bool dicom_reader_available() { return false; }

DicomSliceHeader read_dicom_slice_header(const std::string& path) { no_reader(path); }

void decode_dicom_slice(const DicomSliceHeader& h, std::byte*) { no_reader(h.file); }

}  // namespace meshless
