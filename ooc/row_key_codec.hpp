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

/// Decodes `count` gap-coded keys from [p, end), calling f(key) for each (key = running sum - 1).
/// False when the bytes run out, a varint is longer than 10 bytes or overflows, a gap is 0, a key
/// is >= key_limit, or bytes remain after the last key (f may have been called for earlier keys).
template <class F>
bool decode_row_keys(const unsigned char* p, const unsigned char* end, std::uint64_t count, std::uint64_t key_limit,
                     F&& f) {
    if (count > static_cast<std::uint64_t>(end - p)) return false;  // every key takes >= 1 byte
    std::uint64_t sum = 0;
    for (std::uint64_t k = 0; k < count; ++k) {
        std::uint64_t gap = 0;
        if (p < end && *p < 0x80) {
            gap = *p++;  // the common one-byte gap
        } else {
            int shift = 0;
            for (;;) {
                if (p == end || shift > 63) return false;
                const std::uint64_t byte = *p++;
                if (shift == 63 && byte > 1) return false;
                gap |= (byte & 0x7f) << shift;
                if (byte < 0x80) break;
                shift += 7;
            }
        }
        if (gap == 0 || gap > key_limit - sum) return false;  // sum + gap - 1 must be < key_limit
        sum += gap;
        f(sum - 1);
    }
    return p == end;
}

/// The same, appending the keys to out.
inline bool decode_row_keys(const unsigned char* p, const unsigned char* end, std::uint64_t count,
                            std::uint64_t key_limit, std::vector<std::uint64_t>& out) {
    return decode_row_keys(p, end, count, key_limit, [&](std::uint64_t k) { out.push_back(k); });
}

}  // namespace meshless
