// Gap coding of the sample store's cell-row keys (ooc/sample_store_format.hpp): a bucket's keys
// are strictly increasing; each is stored as the LEB128 varint of its gap to the previous key
// (the first as key + 1, so every gap is >= 1). Cells of a bucket cluster in space, so most gaps
// take one byte (measured: 1.1 bytes per non-constant cell on the lung-sized CT).
// Pure functions; thread-safe. The decoder never reads past `end` and reports malformed input by
// returning false (the caller names the file and bucket).
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

namespace meshless {

/// Bytes of the varint of x (1..10).
inline std::size_t varint_bytes(std::uint64_t x) {
    std::size_t n = 1;
    while (x >= 0x80) {
        x >>= 7;
        ++n;
    }
    return n;
}

/// Appends the varint of x.
inline void put_varint(std::vector<unsigned char>& out, std::uint64_t x) {
    while (x >= 0x80) {
        out.push_back(static_cast<unsigned char>(x | 0x80));
        x >>= 7;
    }
    out.push_back(static_cast<unsigned char>(x));
}

/// Decodes `count` gap-coded keys from [p, end) and appends them (key = running sum - 1) to out.
/// False when the bytes run out, a varint is longer than 10 bytes or overflows, a gap is 0, a key
/// is >= key_limit, or bytes remain after the last key.
bool decode_row_keys(const unsigned char* p, const unsigned char* end, std::uint64_t count, std::uint64_t key_limit,
                     std::vector<std::uint64_t>& out);

}  // namespace meshless
