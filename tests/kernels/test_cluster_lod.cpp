// kernels/cluster_lod: the level- and error-based depth-first traversals of dissertation section
// 6.4 against a brute-force (recursive depth-first) traversal (the same nodes), the per-level and per-error sizes against the
// traversals, and the finest LOD for requests beyond the tree.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <functional>
#include <vector>

#include "kernels/cluster_binary_tree.hpp"
#include "kernels/cluster_lod.hpp"

using namespace meshless;

namespace {

ClusterTree sample_tree() {
    std::vector<Vec3> pos;
    std::vector<double> val;
    for (int k = 0; k < 9; ++k)
        for (int j = 0; j < 11; ++j)
            for (int i = 0; i < 13; ++i) {
                pos.push_back({double(i), double(j), double(k)});
                val.push_back(std::round(50 * std::sin(0.5 * i) * std::cos(0.3 * j + 0.2 * k) + (i * i + j * j < 30 ? 80 : 0)));
            }
    CbtParams p;
    p.max_splits = 900;  // not fully refined: leaves at many depths, internal nodes with small errors
    return build_cluster_tree(pos, val, p);
}

std::vector<std::uint32_t> brute(const std::vector<CbtNode>& nodes, const std::function<bool(const CbtNode&)>& take) {
    std::vector<std::uint32_t> out;
    std::function<void(std::uint32_t)> rec = [&](std::uint32_t i) {
        if (nodes[i].leaf() || take(nodes[i])) {
            out.push_back(i);
            return;
        }
        rec(nodes[i].child);
        rec(nodes[i].child + 1);
    };
    rec(0);
    std::sort(out.begin(), out.end());  // lod_nodes gives node-number order
    return out;
}

}  // namespace

TEST_CASE("LOD traversal: level- and error-based equal a brute-force depth-first traversal", "[kernels][cbt]") {
    const ClusterTree t = sample_tree();
    const auto sizes = lod_sizes_per_level(t.nodes);
    REQUIRE(sizes.size() == t.stats.depth + 1);
    for (std::uint32_t L = 0; L <= t.stats.depth + 2; ++L) {
        const auto got = lod_nodes(t.nodes, LodMode::level, L);
        const auto want = brute(t.nodes, [L](const CbtNode& d) { return d.depth == L; });
        INFO("level " << L);
        CHECK(got == want);
        CHECK(got.size() == sizes[std::min<std::size_t>(L, sizes.size() - 1)]);
        CHECK(lod_request_clamped(t.nodes, LodMode::level, L) == (L > t.stats.depth));
    }
    for (double E : {1e9, t.nodes[0].error, 100.0, 40.0, 10.0, 3.0, 1.0, 0.0}) {
        const auto got = lod_nodes(t.nodes, LodMode::error, E);
        const auto want = brute(t.nodes, [E](const CbtNode& d) { return d.error <= E; });
        INFO("error " << E);
        CHECK(got == want);
        CHECK(lod_size_at_error(t.nodes, E) == got.size());
        for (std::uint32_t i : got) CHECK((t.nodes[i].error <= E || t.nodes[i].leaf()));
    }
    // beyond the tree: the finest LOD (every leaf)
    std::size_t leaves = 0;
    for (const CbtNode& d : t.nodes) leaves += d.leaf();
    CHECK(lod_nodes(t.nodes, LodMode::level, 1000).size() == leaves);
    CHECK(lod_nodes(t.nodes, LodMode::error, -1).size() == leaves);
    CHECK(lod_request_clamped(t.nodes, LodMode::error, t.stats.error_reached * 0.5) == (t.stats.error_reached > 0));
    // the point set carries the centres and values, coarse to fine
    const PointSet ps = lod_point_set(t.nodes, LodMode::level, 5, "v");
    const auto ids = lod_coarse_to_fine_order(t.nodes, lod_nodes(t.nodes, LodMode::level, 5));
    REQUIRE(ps.size() == ids.size());
    for (std::size_t i = 0; i < ids.size(); ++i) {
        CHECK(ps.pos[i].x == t.nodes[ids[i]].centre.x);
        CHECK(ps.value[i] == t.nodes[ids[i]].value);
    }
}

TEST_CASE("LOD order: every prefix of a LOD holds one node below each cluster of a coarser cut", "[kernels][cbt]") {
    const ClusterTree t = sample_tree();
    // parent of each node, to find a node's ancestor at depth k
    std::vector<std::uint32_t> parent(t.nodes.size(), 0);
    for (std::uint32_t i = 0; i < t.nodes.size(); ++i)
        if (!t.nodes[i].leaf()) parent[t.nodes[i].child] = parent[t.nodes[i].child + 1] = i;
    const auto at_depth = [&](std::uint32_t i, std::uint32_t k) {
        while (t.nodes[i].depth > k) i = parent[i];
        return i;
    };
    for (const auto& [mode, threshold] : {std::pair{LodMode::level, 7.0}, std::pair{LodMode::level, 1000.0}, std::pair{LodMode::error, 3.0}}) {
        const auto plain = lod_nodes(t.nodes, mode, threshold);
        const auto order = lod_coarse_to_fine_order(t.nodes, plain);
        auto sorted = order;
        std::sort(sorted.begin(), sorted.end());
        REQUIRE(sorted == plain);  // the same nodes
        std::uint32_t deepest = 0;
        for (std::uint32_t i : plain) deepest = std::max(deepest, t.nodes[i].depth);
        for (std::uint32_t k = 0; k <= deepest; ++k) {
            // the level-k cut above this LOD: the level-k LOD's nodes that are ancestors of (or are) LOD nodes
            std::vector<std::uint32_t> cut;
            for (std::uint32_t i : plain) cut.push_back(at_depth(i, k));
            std::sort(cut.begin(), cut.end());
            cut.erase(std::unique(cut.begin(), cut.end()), cut.end());
            // the first cut.size() nodes of the order: one below each cluster of the cut
            std::vector<std::uint32_t> seen;
            for (std::size_t j = 0; j < cut.size(); ++j) seen.push_back(at_depth(order[j], k));
            std::sort(seen.begin(), seen.end());
            INFO("k " << k << ", threshold " << threshold);
            CHECK(seen == cut);
        }
    }
}

TEST_CASE("LOD by count: the leaves after the first N - 1 splits, any N", "[kernels][cbt]") {
    const ClusterTree t = sample_tree();
    const std::uint64_t leaves = t.stats.splits + 1;
    for (std::uint64_t n : {std::uint64_t{1}, std::uint64_t{2}, std::uint64_t{3}, std::uint64_t{57}, leaves - 1, leaves}) {
        // brute force: nodes numbered below 2(n-1)+1 exist after n-1 splits; of those, the ones not split yet
        const std::uint64_t cut = 2 * (n - 1) + 1;
        std::vector<std::uint32_t> want;
        for (std::uint32_t i = 0; i < cut; ++i)
            if (t.nodes[i].leaf() || t.nodes[i].child >= cut) want.push_back(i);
        const auto got = lod_nodes(t.nodes, LodMode::count, static_cast<double>(n));
        CHECK(got == want);
        CHECK(got.size() == n);
        CHECK_FALSE(lod_request_clamped(t.nodes, LodMode::count, static_cast<double>(n)));
    }
    CHECK(lod_request_clamped(t.nodes, LodMode::count, static_cast<double>(leaves + 1)));
    CHECK(lod_nodes(t.nodes, LodMode::count, static_cast<double>(leaves + 5)).size() == leaves);  // the finest
}
