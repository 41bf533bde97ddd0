#include "ooc/row_key_codec.hpp"

namespace meshless {

bool decode_row_keys(const unsigned char* p, const unsigned char* end, std::uint64_t count, std::uint64_t key_limit,
                     std::vector<std::uint64_t>& out) {
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
        out.push_back(sum - 1);
    }
    return p == end;
}

}  // namespace meshless
