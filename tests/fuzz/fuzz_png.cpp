// libFuzzer target for the PNG reader (formats/png_reader.hpp; meshless render --compare).
// Built only with Clang and -DMESHLESS_BUILD_FUZZ=ON (see fuzz_ply.cpp for the commands):
//   cmake --build build-fuzz --target fuzz_png
//   mkdir -p corpus-png && meshless render VOL -o corpus-png/a.png --size 16x16
//   build-fuzz/tests/fuzz/fuzz_png corpus-png -max_total_time=60 -rss_limit_mb=512
// The only acceptable failure is FormatError; anything else (a crash, a sanitizer report, another
// exception, a hang, an allocation beyond -rss_limit_mb) is a defect. Oracle: a decoded picture has
// sides in 1..16384 and exactly 3 bytes per pixel.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <span>

#include "formats/png_reader.hpp"
#include "kernels/errors.hpp"

using namespace meshless;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    try {
        const Image img = decode_png(std::span<const unsigned char>(data, size), "fuzz");
        if (img.width < 1 || img.height < 1 || img.width > kMaxPngSide || img.height > kMaxPngSide ||
            img.rgb.size() != 3 * static_cast<std::size_t>(img.width) * static_cast<std::size_t>(img.height))
            std::abort();
    } catch (const FormatError&) {
    }
    return 0;
}
