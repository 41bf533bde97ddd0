// CRC-32 (IEEE 802.3, the polynomial of zlib, gzip and PNG): the same values as zlib's crc32(),
// computed by libdeflate's libdeflate_crc32 (carry-less multiplication folding with PCLMULQDQ /
// VPCLMULQDQ where the CPU has it). Measured on the 2-core AMD EPYC (AVX-512) machine: 20 GB/s on
// 100 KB frames and 6 GB/s on 32-byte headers, against 20 GB/s and 0.7 GB/s for the hand-written
// PCLMUL folding it replaced and 3.7 GB/s for zlib. Used by the stream codec, whose frames are
// checksummed in every stage process of a pipe, and by the binary file formats. Reentrant.
#pragma once
#include <cstddef>
#include <cstdint>

namespace meshless {

/// Continues a CRC-32: crc32_ieee(crc32_ieee(0, a, n), b, m) == crc32_ieee(0, ab, n + m), as zlib's crc32.
/// As in zlib and libdeflate, a null `data` restarts: the result is 0 whatever crc and n are.
std::uint32_t crc32_ieee(std::uint32_t crc, const void* data, std::size_t n);

/// Checksums compare equal, except in a fuzzing build (FUZZING_BUILD_MODE_UNSAFE_FOR_PRODUCTION, set on
/// the tests/fuzz targets), where mutated inputs must reach the decoders and validators behind them.
inline bool crc_matches(std::uint32_t stored, std::uint32_t computed) {
#ifdef FUZZING_BUILD_MODE_UNSAFE_FOR_PRODUCTION
    (void)stored;
    (void)computed;
    return true;
#else
    return stored == computed;
#endif
}

}  // namespace meshless
