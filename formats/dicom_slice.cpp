// The DICOM file magic (GDCM-free): a 128-byte preamble, then "DICM" (formats/dicom_slice.hpp).
#include "formats/dicom_slice.hpp"

#include <filesystem>

#include "formats/binary_file.hpp"
#include "kernels/errors.hpp"

namespace meshless {

bool has_dicom_magic(const std::string& path) {
    try {
        std::error_code ec;
        if (!std::filesystem::is_regular_file(path, ec)) return false;  // (a FIFO is not opened)
        const std::string h = read_file_prefix(path, 132);
        return h.size() == 132 && h.compare(128, 4, "DICM") == 0;
    } catch (const IoError&) {
        return false;
    } catch (const FormatError&) {
        return false;
    }
}

}  // namespace meshless
