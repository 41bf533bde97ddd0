// libFuzzer target for the RLE Lossless decoder (formats/dicom_rle.hpp: its checks, then the
// decoding into a buffer of exactly the frame's bytes), alone, since a DICOM file's structure walk
// would stop most mutations before they reach it (fuzz_dicom covers the file around it).
// Input: u16 little-endian pixel count (rows x columns, at most 65535), u8 bytes a sample (1 or 2),
// then the Pixel Data element's value (items). The only acceptable failure is FormatError; a check
// that passes promises every run stays inside its segment and the output (the sanitizers watch).
// Built and run like every target: scripts/fuzz.sh SECONDS BUILD fuzz_dicom_rle.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>
#include <vector>

#include "formats/dicom_rle.hpp"
#include "kernels/errors.hpp"

using namespace meshless;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size < 3) return 0;
    std::uint16_t pixels;
    std::memcpy(&pixels, data, 2);
    const int segments = data[2] % 2 + 1;
    try {
        std::vector<std::byte> out(std::size_t{pixels} * static_cast<std::size_t>(segments));
        decode_rle_pixel_data(std::span<const unsigned char>(data + 3, size - 3), 0, pixels, segments, "fuzz", out.data());
    } catch (const FormatError&) {
        return 0;
    }
    return 0;
}
