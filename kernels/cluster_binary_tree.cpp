#include "kernels/cluster_binary_tree.hpp"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <queue>
#include <vector>

#include "kernels/cluster_pca_split.hpp"
#include "kernels/cluster_value.hpp"
#include "kernels/errors.hpp"
#include "kernels/fixed_chunks.hpp"

namespace meshless {

namespace {

struct QueueEntry {
    double error;
    std::uint32_t node;
};
struct WorseFirst {  // priority_queue's "less": the top is the largest error, then the smallest node
    bool operator()(const QueueEntry& a, const QueueEntry& b) const {
        if (a.error != b.error) return a.error < b.error;
        return a.node > b.node;
    }
};

struct SplitResult {
    bool skipped = false;
    std::uint32_t behind = 0;  // samples of the first child
    ClusterValue child[2];
};

constexpr std::size_t kBatch = 64;
constexpr std::size_t kPadPerThread = 16;  // clusters per batch, per core of the task arena (with the certain ones)

}  // namespace

ClusterTree build_cluster_tree(std::span<const Vec3> pos, std::span<const double> value, const CbtParams& params,
                               CbtProgress* progress) {
    const auto t0 = std::chrono::steady_clock::now();
    if (pos.size() != value.size()) throw InvalidArgument("cluster tree: positions and values differ in count");
    if (params.min_cluster < 2) throw InvalidArgument("cluster tree: min_cluster must be >= 2");
    if (params.neighbours < 1) throw InvalidArgument("cluster tree: neighbours must be >= 1");
    if (!std::isfinite(params.max_error) || params.max_error < 0)
        throw InvalidArgument("cluster tree: max_error must be a finite number >= 0");
    if (!std::isfinite(params.hardy_c_rel) || params.hardy_c_rel < 0 || !std::isfinite(params.hardy_c_world) ||
        params.hardy_c_world < 0)
        throw InvalidArgument("cluster tree: Hardy's c must be a finite number >= 0");
    if (pos.size() >= 0xFFFFFFFFull) throw InvalidArgument("cluster tree: 2^32 samples or more");

    ClusterTree tree;
    tree.params = params;
    CbtStats& st = tree.stats;
    std::vector<std::uint32_t> idx;
    idx.reserve(pos.size());
    for (std::size_t i = 0; i < pos.size(); ++i) {
        const Vec3& p = pos[i];
        if (std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z) && std::isfinite(value[i]))
            idx.push_back(static_cast<std::uint32_t>(i));
        else
            ++st.dropped_nonfinite;
    }
    const std::size_t n = idx.size();
    if (n < 2)
        throw InvalidArgument("cluster tree: " + std::to_string(n) + " finite sample" + (n == 1 ? "" : "s") +
                              ", at least 2 needed" +
                              (st.dropped_nonfinite ? " (" + std::to_string(st.dropped_nonfinite) + " NaN/Inf dropped)" : ""));
    st.samples = n;
    Vec3 lo = pos[idx[0]], hi = lo;
    double vlo = value[idx[0]], vhi = vlo;
    for (std::uint32_t j : idx) {
        lo = {std::min(lo.x, pos[j].x), std::min(lo.y, pos[j].y), std::min(lo.z, pos[j].z)};
        hi = {std::max(hi.x, pos[j].x), std::max(hi.y, pos[j].y), std::max(hi.z, pos[j].z)};
        vlo = std::min(vlo, value[j]);
        vhi = std::max(vhi, value[j]);
    }
    tree.bounds = {lo, hi};
    tree.value_range = {vlo, vhi};
    const double diag = norm(hi - lo);
    if (!(diag > 0)) throw InvalidArgument("cluster tree: all " + std::to_string(n) + " samples lie at one position");
    const double c = params.hardy_c_world > 0 ? params.hardy_c_world : params.hardy_c_rel * diag;
    st.hardy_c_world = c;
    double pos_scale = 1, value_scale = 1;
    if (params.scaling == PcaScaling::normalised) {
        pos_scale = 1 / diag;
        value_scale = vhi > vlo ? 1 / (vhi - vlo) : 1;
    }

    tbb::enumerable_thread_specific<ClusterValueEvaluator> evaluators(
        [&] { return ClusterValueEvaluator(params.neighbours, c); });
    // A big cluster's evaluation waits on oneTBB tasks, and a waiting thread may pick up another
    // cluster's task: it gets its own evaluator, so a thread's scratch is never used re-entrantly.
    auto evaluate = [&](std::uint32_t first, std::uint32_t count) {
        const std::span<const std::uint32_t> r(idx.data() + first, count);
        if (count >= chunks::kParallelItems) {
            ClusterValueEvaluator own(params.neighbours, c);
            return own.evaluate(pos, value, r);
        }
        return evaluators.local().evaluate(pos, value, r);
    };

    std::vector<CbtNode>& nodes = tree.nodes;
    std::vector<std::uint32_t> first;   // per node: start of its range in idx
    std::vector<double> mean_value;     // per node: the PCA's value centre
    auto add_node = [&](const ClusterValue& v, std::uint32_t start, std::uint32_t count, std::uint32_t depth) {
        CbtNode d;
        d.centre = v.centre;
        d.value = v.value;
        d.error = v.error;
        d.count = count;
        d.depth = depth;
        nodes.push_back(d);
        first.push_back(start);
        mean_value.push_back(v.mean_value);
        return static_cast<std::uint32_t>(nodes.size() - 1);
    };
    std::priority_queue<QueueEntry, std::vector<QueueEntry>, WorseFirst> queue;
    auto offer = [&](std::uint32_t id) {
        const CbtNode& d = nodes[id];
        if (d.count >= params.min_cluster && d.error > params.max_error) queue.push({d.error, id});
    };
    {  // reserve what the refinement can make: pages never written cost no memory
        const std::uint64_t most = std::min<std::uint64_t>(params.max_splits, n - 1);
        nodes.reserve(2 * most + 1);
        first.reserve(2 * most + 1);
        mean_value.reserve(2 * most + 1);
    }
    add_node(evaluate(0, static_cast<std::uint32_t>(n)), 0, static_cast<std::uint32_t>(n), 0);
    offer(0);

    auto split = [&](std::uint32_t id) {
        SplitResult r;
        const CbtNode d = nodes[id];
        const std::uint32_t start = first[id];
        std::span<std::uint32_t> range(idx.data() + start, d.count);
        const ClusterSplitPlane plane =
            pca_split_plane(pos, value, range, d.centre, mean_value[id], pos_scale, value_scale);
        const std::size_t behind = plane.normal.x == 0 && plane.normal.y == 0 && plane.normal.z == 0
                                       ? 0
                                       : partition_by_plane(pos, range, d.centre, plane.normal);
        if (behind == 0 || behind == d.count) {
            r.skipped = true;
            return r;
        }
        r.behind = static_cast<std::uint32_t>(behind);
        const std::uint32_t m = r.behind;
        if (d.count >= chunks::kParallelItems) {
            tbb::parallel_invoke([&] { r.child[0] = evaluate(start, m); }, [&] { r.child[1] = evaluate(start + m, d.count - m); });
        } else {
            r.child[0] = evaluate(start, m);
            r.child[1] = evaluate(start + m, d.count - m);
        }
        return r;
    };

    // Clusters taken from the queue and split speculatively wait in `ready` (same order as the
    // queue) until the serial order reaches them.
    struct Ready {
        QueueEntry e;
        SplitResult r;
    };
    auto ready_less = [](const Ready& a, const Ready& b) { return WorseFirst{}(a.e, b.e); };
    std::priority_queue<Ready, std::vector<Ready>, decltype(ready_less)> ready(ready_less);
    std::vector<QueueEntry> batch;
    std::vector<SplitResult> results;
    const std::size_t pad = kPadPerThread * static_cast<std::size_t>(std::max(1, tbb::this_task_arena::max_concurrency()));
    while ((!queue.empty() || !ready.empty()) && st.splits < params.max_splits) {
        if (ready.empty() || (!queue.empty() && WorseFirst{}(ready.top().e, queue.top()))) {
            // the next cluster in serial order has no result yet: split it and the next worst ones
            batch.clear();
            const std::uint64_t left = params.max_splits - st.splits;  // splits still allowed
            while (!queue.empty() && batch.size() < kBatch && batch.size() < left) {
                // the entries ahead of ready.top() in serial order are split for certain; past them
                // only enough to keep the threads busy (speculation past the last split is waste)
                const bool ahead = !ready.empty() && WorseFirst{}(ready.top().e, queue.top());
                if (!batch.empty() && !ahead &&
                    (batch.size() >= pad || ready.size() + batch.size() >= left / 8))
                    break;  // (the first is the next cluster in serial order: always split)
                batch.push_back(queue.top());
                queue.pop();
            }
            results.assign(batch.size(), SplitResult{});
            if (batch.size() == 1) {
                results[0] = split(batch[0].node);
            } else {
                tbb::parallel_for(tbb::blocked_range<std::size_t>(0, batch.size(), 1), [&](const tbb::blocked_range<std::size_t>& br) {
                    for (std::size_t i = br.begin(); i != br.end(); ++i) results[i] = split(batch[i].node);
                });
            }
            for (std::size_t i = 0; i < batch.size(); ++i) ready.push(Ready{batch[i], results[i]});
            if (progress) progress->splits_done(st.splits);
            continue;
        }
        const QueueEntry e = ready.top().e;
        const SplitResult r = ready.top().r;
        ready.pop();
        if (r.skipped) {
            nodes[e.node].flags |= kCbtSkippedSplit;
            ++st.skipped;
            continue;
        }
        const std::uint32_t start = first[e.node], count = nodes[e.node].count, depth = nodes[e.node].depth + 1;
        const std::uint32_t a = add_node(r.child[0], start, r.behind, depth);
        const std::uint32_t b = add_node(r.child[1], start + r.behind, count - r.behind, depth);
        nodes[e.node].child = a;
        ++st.splits;
        st.depth = std::max(st.depth, depth);
        offer(a);
        offer(b);
    }
    st.speculative_unused = ready.size();
    st.error_reached = 0;
    for (const CbtNode& d : nodes)
        if (d.leaf()) st.error_reached = std::max(st.error_reached, d.error);
    st.memory_bytes = idx.size() * 4 + nodes.size() * (sizeof(CbtNode) + 12);
    st.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return tree;
}

}  // namespace meshless
