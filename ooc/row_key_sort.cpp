#include "ooc/row_key_sort.hpp"

#include <algorithm>
#include <array>
#include <bit>

namespace meshless {

void sort_unique_row_keys(std::vector<std::uint64_t>& keys, std::uint64_t key_limit) {
    constexpr int kDigit = 11;
    constexpr std::size_t kBins = std::size_t{1} << kDigit;
    const int bits = key_limit > 1 ? std::bit_width(key_limit - 1) : 1;
    if (keys.size() < 256) {
        std::sort(keys.begin(), keys.end());
    } else {
        std::vector<std::uint64_t> tmp(keys.size());
        std::array<std::size_t, kBins> count{};
        for (int shift = 0; shift < bits; shift += kDigit) {
            count.fill(0);
            for (const std::uint64_t k : keys) ++count[(k >> shift) & (kBins - 1)];
            std::size_t sum = 0;
            for (std::size_t& c : count) {
                const std::size_t n = c;
                c = sum;
                sum += n;
            }
            for (const std::uint64_t k : keys) tmp[count[(k >> shift) & (kBins - 1)]++] = k;
            keys.swap(tmp);
        }
    }
    keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
}

}  // namespace meshless
