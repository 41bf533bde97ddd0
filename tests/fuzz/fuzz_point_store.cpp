// libFuzzer target for the point store codec (formats/point_store_format.hpp, ".mlc"): header,
// footer and index validation, then every brick's frame (zstd), its points and their checks against
// the index (Morton keys inside the cell, bounds, value range) through parse_point_store_bytes, the
// in-memory entry point of the reader.
//
// Built only with Clang and -DMESHLESS_BUILD_FUZZ=ON; scripts/fuzz.sh seeds it with stores that
// `meshless convert POINTS -o s.mlc --brick-points 16` writes, or by hand:
//   cmake --build build-fuzz --target fuzz_point_store
//   mkdir -p corpus-mlc && build/cli/meshless convert ../shared/data/scattered/sparsePoints.txt \
//     -o corpus-mlc/sparse.mlc --brick-points 4
//   build-fuzz/tests/fuzz/fuzz_point_store corpus-mlc -max_total_time=60
// Compiled with FUZZING_BUILD_MODE_UNSAFE_FOR_PRODUCTION, so wrong checksums are accepted and the
// mutations reach the decoders and validators behind them. The only acceptable failure is
// FormatError; anything else (a crash, a sanitizer report, another exception, a hang, an allocation
// beyond -rss_limit_mb) is a defect. Oracle: a store that parses holds as many points in its bricks
// as its header says, each brick within 1..B points.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>

#include "formats/point_store_format.hpp"
#include "kernels/errors.hpp"

using namespace meshless;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::span<const unsigned char> bytes(data, size);
    try {
        const PointStoreReadAt read = [&](void* dst, std::size_t n, std::uint64_t off) {
            if (off > size || n > size - off) throw FormatError("fuzz: truncated");
            std::memcpy(dst, data + off, n);
        };
        const PointStoreLayout head = decode_point_store_layout(read, size, "fuzz");
        // a 64 KiB input may claim bricks of 2^20 points that zstd's RLE blocks really hold: decode
        // them only up to 4 M points in all (128 MB of decompression), so one input stays fast
        if (head.info.points > (std::uint64_t{1} << 22)) return 0;
        const PointStoreLayout l = parse_point_store_bytes(bytes, "fuzz");
        std::uint64_t n = 0;
        for (const auto& e : l.bricks) {
            if (e.count < 1 || e.count > l.info.brick_points) __builtin_trap();
            n += e.count;
        }
        if (n != l.info.points) __builtin_trap();
    } catch (const FormatError&) {
    }
    return 0;
}
