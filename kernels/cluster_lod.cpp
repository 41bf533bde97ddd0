#include "kernels/cluster_lod.hpp"

#include <algorithm>

namespace meshless {

namespace {

/// The depth-first selection of section 6.4 as one pass in node-number order: a child is numbered
/// after its parent, so when node i is reached every ancestor has been decided; `covered` marks the
/// nodes below a node already taken. Sequential over the nodes (a DFS jumps through them).
template <class Take>
void traverse(std::span<const CbtNode> nodes, Take&& take_here, std::vector<std::uint32_t>* out, std::uint64_t* count) {
    const std::size_t n = nodes.size();
    std::vector<std::uint8_t> covered(n, 0);
    for (std::size_t i = 0; i < n; ++i) {
        const CbtNode& d = nodes[i];
        bool below = covered[i] != 0;
        if (!below && (d.leaf() || take_here(d))) {
            if (out) out->push_back(static_cast<std::uint32_t>(i));
            if (count) ++*count;
            below = true;
        }
        if (below && !d.leaf()) covered[d.child] = covered[d.child + 1] = 1;
    }
}

}  // namespace

std::vector<std::uint32_t> lod_nodes(std::span<const CbtNode> nodes, LodMode mode, double threshold) {
    std::vector<std::uint32_t> out;
    if (mode == LodMode::level) {
        const double L = threshold;
        traverse(nodes, [L](const CbtNode& d) { return static_cast<double>(d.depth) >= L; }, &out, nullptr);
    } else if (mode == LodMode::count) {
        // the first k = N - 1 splits made nodes 1 .. 2k: a node whose children are numbered later is cut there
        const double cut = 2 * (std::max(threshold, 1.0) - 1) + 1;
        traverse(nodes, [cut](const CbtNode& d) { return static_cast<double>(d.child) >= cut; }, &out, nullptr);
    } else {
        traverse(nodes, [threshold](const CbtNode& d) { return d.error <= threshold; }, &out, nullptr);
    }
    return out;
}

std::vector<std::uint32_t> lod_coarse_to_fine_order(std::span<const CbtNode> nodes, std::vector<std::uint32_t> ids) {
    // key[i]: the depth of the shallowest cluster node i's representative chain starts at. A
    // split passes its cluster's key to the larger child (the first on a tie) and starts a new
    // chain at the other child's depth; children are numbered after their parents, so one pass
    // in number order sees every parent before its children.
    std::vector<std::uint32_t> key(nodes.size(), 0);
    for (std::size_t i = 0; i < nodes.size(); ++i) {
        const CbtNode& d = nodes[i];
        if (d.leaf()) continue;
        const std::uint32_t a = d.child, b = d.child + 1;
        const bool first_larger = nodes[a].count >= nodes[b].count;
        key[first_larger ? a : b] = key[i];
        key[first_larger ? b : a] = nodes[first_larger ? b : a].depth;
    }
    std::stable_sort(ids.begin(), ids.end(), [&](std::uint32_t x, std::uint32_t y) { return key[x] < key[y]; });
    return ids;
}

PointSet lod_point_set(std::span<const CbtNode> nodes, LodMode mode, double threshold, const std::string& value_name) {
    const std::vector<std::uint32_t> ids = lod_coarse_to_fine_order(nodes, lod_nodes(nodes, mode, threshold));
    PointSet ps;
    ps.pos.resize(ids.size());
    ps.value.resize(ids.size());
    for (std::size_t i = 0; i < ids.size(); ++i) {
        ps.pos[i] = nodes[ids[i]].centre;
        ps.value[i] = nodes[ids[i]].value;
    }
    ps.value_name = value_name;
    ps.blocks.push_back(PointSetBlock{"lod", {static_cast<std::int64_t>(ids.size()), 1, 1}, 0, ids.size()});
    return ps;
}

std::vector<std::uint64_t> lod_sizes_per_level(std::span<const CbtNode> nodes) {
    std::uint32_t depth = 0;
    for (const CbtNode& d : nodes) depth = std::max(depth, d.depth);
    std::vector<std::uint64_t> at(depth + 1, 0), leaves(depth + 1, 0);
    for (const CbtNode& d : nodes) {
        ++at[d.depth];
        if (d.leaf()) ++leaves[d.depth];
    }
    // LOD(L) = nodes at depth L + leaves above L
    std::vector<std::uint64_t> out(depth + 1);
    std::uint64_t above = 0;
    for (std::uint32_t L = 0; L <= depth; ++L) {
        out[L] = at[L] + above;
        above += leaves[L];
    }
    return out;
}

std::uint64_t lod_size_at_error(std::span<const CbtNode> nodes, double error) {
    std::uint64_t n = 0;
    traverse(nodes, [error](const CbtNode& d) { return d.error <= error; }, nullptr, &n);
    return n;
}

bool lod_request_clamped(std::span<const CbtNode> nodes, LodMode mode, double threshold) {
    const CbtStats s = cluster_tree_stats(nodes);
    if (mode == LodMode::level) return threshold > static_cast<double>(s.depth);
    if (mode == LodMode::count) return threshold > static_cast<double>(s.splits + 1);
    return threshold < s.error_reached;
}

}  // namespace meshless
