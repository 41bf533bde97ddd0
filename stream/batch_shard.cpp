#include "stream/batch_shard.hpp"

#include <algorithm>
#include <filesystem>
#include <numeric>

namespace meshless {

namespace fs = std::filesystem;

std::uint64_t input_bytes(const std::string& path) {
    std::error_code ec;
    if (fs::is_directory(path, ec)) {
        std::uint64_t sum = 0;
        for (fs::recursive_directory_iterator it(path, fs::directory_options::skip_permission_denied, ec), end; !ec && it != end;
             it.increment(ec)) {
            std::error_code fe;
            if (it->is_regular_file(fe)) sum += it->file_size(fe);
        }
        return std::max<std::uint64_t>(1, sum);
    }
    const auto bytes = fs::file_size(path, ec);
    return ec ? 1 : std::max<std::uint64_t>(1, bytes);
}

std::vector<std::size_t> size_order(const std::vector<BatchItem>& items, std::vector<std::uint64_t>* bytes_out) {
    std::vector<std::uint64_t> bytes(items.size());
    for (std::size_t i = 0; i < items.size(); ++i) bytes[i] = items[i].error.empty() ? input_bytes(items[i].path) : 1;
    std::vector<std::size_t> order(items.size());
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return bytes[a] > bytes[b]; });
    if (bytes_out) *bytes_out = std::move(bytes);
    return order;
}

std::vector<BatchItem> shard_items(const std::vector<BatchItem>& items, std::uint32_t k, std::uint32_t n) {
    if (n <= 1) return items;
    const std::vector<std::size_t> order = size_order(items);
    std::vector<bool> mine(items.size(), false);
    for (std::size_t r = 0; r < order.size(); ++r)
        if (r % n == k) mine[order[r]] = true;
    std::vector<BatchItem> out;
    for (std::size_t i = 0; i < items.size(); ++i)
        if (mine[i]) out.push_back(items[i]);
    return out;
}

}  // namespace meshless
