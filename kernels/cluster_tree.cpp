#include "kernels/cluster_tree.hpp"

#include <algorithm>
#include <cmath>

namespace meshless {

std::string validate_cluster_tree(std::span<const CbtNode> nodes, std::uint64_t samples) {
    if (nodes.empty()) return "no nodes";
    if (nodes.size() % 2 == 0) return std::to_string(nodes.size()) + " nodes: a binary tree of splits holds an odd number";
    if (nodes.size() > 0xFFFFFFFFull) return "too many nodes";
    const std::size_t n = nodes.size();
    auto at = [](std::size_t i, const std::string& what) { return "node " + std::to_string(i) + ": " + what; };
    std::vector<bool> referenced(n, false);
    if (nodes[0].depth != 0) return at(0, "the root has depth " + std::to_string(nodes[0].depth));
    if (nodes[0].count != samples)
        return at(0, "the root holds " + std::to_string(nodes[0].count) + " samples, the tree " + std::to_string(samples));
    for (std::size_t i = 0; i < n; ++i) {
        const CbtNode& d = nodes[i];
        if (!std::isfinite(d.centre.x) || !std::isfinite(d.centre.y) || !std::isfinite(d.centre.z)) return at(i, "non-finite centre");
        if (!std::isfinite(d.value)) return at(i, "non-finite value");
        if (!std::isfinite(d.error) || d.error < 0) return at(i, "error not a finite number >= 0");
        if (d.count == 0) return at(i, "empty cluster");
        if ((d.flags & ~kCbtSkippedSplit) != 0) return at(i, "unknown flags " + std::to_string(d.flags));
        if (d.leaf()) continue;
        if ((d.flags & kCbtSkippedSplit) != 0) return at(i, "a skipped split with children");
        if (d.child <= i || d.child >= n - 1)
            return at(i, "child " + std::to_string(d.child) + " out of range (after " + std::to_string(i) + ", before " +
                             std::to_string(n - 1) + ")");
        for (std::uint32_t c = d.child; c <= d.child + 1; ++c) {
            if (referenced[c]) return at(c, "child of two parents");
            referenced[c] = true;
            if (nodes[c].depth != d.depth + 1) return at(c, "depth " + std::to_string(nodes[c].depth) + ", parent's + 1 expected");
        }
        if (static_cast<std::uint64_t>(nodes[d.child].count) + nodes[d.child + 1].count != d.count)
            return at(i, "children hold " + std::to_string(static_cast<std::uint64_t>(nodes[d.child].count) + nodes[d.child + 1].count) +
                             " samples, the node " + std::to_string(d.count));
    }
    for (std::size_t i = 1; i < n; ++i)
        if (!referenced[i]) return at(i, "not reachable from the root");
    return {};
}

CbtStats cluster_tree_stats(std::span<const CbtNode> nodes) {
    CbtStats s;
    if (nodes.empty()) return s;
    s.samples = nodes[0].count;
    for (const CbtNode& d : nodes) {
        s.depth = std::max(s.depth, d.depth);
        if (d.leaf()) {
            s.error_reached = std::max(s.error_reached, d.error);
            if (d.flags & kCbtSkippedSplit) ++s.skipped;
        } else {
            ++s.splits;
        }
    }
    return s;
}

}  // namespace meshless
