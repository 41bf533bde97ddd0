#include "kernels/cluster_binary_tree.hpp"
#include "kernels/sample_set_hash.hpp"

#include <tbb/concurrent_vector.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <functional>
#include <limits>
#include <mutex>
#include <vector>

#include "kernels/cluster_pca_split.hpp"
#include "kernels/cluster_value.hpp"
#include "kernels/errors.hpp"
#include "kernels/fixed_chunks.hpp"

namespace meshless {

namespace {

struct QueueEntry {
    double error;  // the split priority (split_key): sigma_c, or the weighted one
    std::uint32_t node;
    double prio;  // min of the errors from the root down to this node: the serial order splits in falling prio
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

constexpr std::uint32_t kNoSpec = 0xFFFFFFFFu;
constexpr std::uint64_t kPadSplits = 64;  // a round computes at most the splits left + this
constexpr std::uint64_t kProgressEvery = 1024;  // splits computed between progress reports
constexpr std::uint64_t kRoundsAtLeast = 16;  // a round aims at max(4096, most splits / 16) / 2 splits at most: bounds the waiting results

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
    if (!(params.size_term >= 0 && params.size_term <= 100))
        throw InvalidArgument("cluster tree: the size term must be in [0, 100]");
    if (params.order != CbtSplitOrder::max_error && params.order != CbtSplitOrder::weighted)
        throw InvalidArgument("cluster tree: unknown split order");
    if (params.value != CbtValueKind::fit && params.value != CbtValueKind::mean)
        throw InvalidArgument("cluster tree: unknown cluster value kind");
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
    tree.samples_hash = sample_set_hash(pos, value);
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
        [&] { return ClusterValueEvaluator(params.neighbours, c, params.value); });
    // A big cluster's evaluation waits on oneTBB tasks, and a waiting thread may pick up another
    // cluster's task: it gets its own evaluator, so a thread's scratch is never used re-entrantly.
    auto evaluate = [&](std::uint32_t first, std::uint32_t count) {
        const std::span<const std::uint32_t> r(idx.data() + first, count);
        if (count >= chunks::kParallelItems) {
            ClusterValueEvaluator own(params.neighbours, c, params.value);
            return own.evaluate(pos, value, r);
        }
        return evaluators.local().evaluate(pos, value, r);
    };

    // the split priority of a cluster (CbtSplitOrder); t^2 = (size term x value range)^2
    const double t2 = std::pow(params.size_term * (vhi - vlo), 2);
    const bool weighted = params.order == CbtSplitOrder::weighted;
    auto split_key = [&](double error, std::uint32_t count) {
        return weighted ? static_cast<double>(count) * (error * error + t2) : error;
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
    // The queue in two tiers: a heap (WorseFirst) of the entries with prio >= theta, and the others
    // unordered. The serial order pops the largest prio in the queue (see the header), so while the
    // heap has entries its top is the queue's top, and the heap stays small (a round's worth).
    // the size term also splits exact clusters, unless a max_error asks to stop at that error
    const bool split_exact = weighted && t2 > 0 && params.max_error == 0;
    auto offerable = [&](std::uint32_t count, double error) {
        return count >= params.min_cluster && (error > params.max_error || split_exact);
    };
    std::vector<QueueEntry> queue, below;
    double theta = -std::numeric_limits<double>::infinity();
    auto offer = [&](std::uint32_t id, double parent_prio) {
        const CbtNode& d = nodes[id];
        if (offerable(d.count, d.error)) {
            const double key = split_key(d.error, d.count);
            const QueueEntry q{key, id, std::min(parent_prio, key)};
            if (q.prio >= theta) {
                queue.push_back(q);
                std::push_heap(queue.begin(), queue.end(), WorseFirst{});
            } else {
                below.push_back(q);
            }
        }
    };
    {  // reserve what the refinement can make: pages never written cost no memory
        const std::uint64_t most = std::min<std::uint64_t>(params.max_splits, n - 1);
        nodes.reserve(2 * most + 1);
        first.reserve(2 * most + 1);
        mean_value.reserve(2 * most + 1);
    }
    add_node(evaluate(0, static_cast<std::uint32_t>(n)), 0, static_cast<std::uint32_t>(n), 0);
    offer(0, std::numeric_limits<double>::infinity());

    // splits the cluster idx[start, start + count): a pure function of its samples
    auto split = [&](std::uint32_t start, std::uint32_t count, const Vec3& centre, double mean) {
        SplitResult r;
        std::span<std::uint32_t> range(idx.data() + start, count);
        const ClusterSplitPlane plane = pca_split_plane(pos, value, range, centre, mean, pos_scale, value_scale);
        const std::size_t behind = plane.normal.x == 0 && plane.normal.y == 0 && plane.normal.z == 0
                                       ? 0
                                       : partition_by_plane(pos, range, centre, plane.normal);
        if (behind == 0 || behind == count) {
            r.skipped = true;
            return r;
        }
        r.behind = static_cast<std::uint32_t>(behind);
        const std::uint32_t m = r.behind;
        if (count >= chunks::kParallelItems) {
            tbb::parallel_invoke([&] { r.child[0] = evaluate(start, m); }, [&] { r.child[1] = evaluate(start + m, count - m); });
        } else {
            r.child[0] = evaluate(start, m);
            r.child[1] = evaluate(start + m, count - m);
        }
        return r;
    };

    // Rounds of speculation (see the header): every split computed ahead is a Spec, found from the
    // queued node it belongs to (spec_of) or from its parent's Spec (child_spec).
    struct Spec {
        SplitResult r;
        std::uint32_t child_spec[2] = {kNoSpec, kNoSpec};
    };
    tbb::concurrent_vector<Spec> specs;
    std::vector<std::uint32_t> free_specs;  // slots of applied Specs, reused by the next round
    std::vector<std::uint32_t> spec_of(1, kNoSpec);
    spec_of.reserve(nodes.capacity());
    std::uint64_t computed = 0;  // splits computed (applied or not)
    std::mutex progress_mutex;   // the progress callback is called by one thread at a time
    // samples in computed clusters that will not be split (not offerable, or their split was skipped):
    // with no max_splits to stop the build, the share of the samples that reached their leaf
    std::atomic<std::uint64_t> settled{offerable(nodes[0].count, nodes[0].error) ? 0 : n};
    std::atomic<std::uint64_t> work{0};  // samples the computed splits took

    const std::uint64_t most_splits = std::min<std::uint64_t>(params.max_splits, n - 1);

    // One round: every queued cluster whose priority is >= tau, and each one's descendants down to
    // priority tau, get their split computed (in parallel, subtrees on their own tasks).
    auto expand_round = [&](double tau, std::int64_t budget_splits) {
        std::atomic<std::size_t> next_free{0};
        std::atomic<std::int64_t> budget{budget_splits};
        std::atomic<std::uint64_t> made{0};
        auto alloc = [&]() -> std::uint32_t {
            const std::size_t f = next_free.fetch_add(1, std::memory_order_relaxed);
            if (f < free_specs.size()) return free_specs[f];
            return static_cast<std::uint32_t>(specs.grow_by(1) - specs.begin());
        };
        // node: the cluster [start, start + count) with its centre and value mean; slot: where its Spec goes
        std::function<void(std::uint32_t, std::uint32_t, const Vec3&, double, double, std::uint32_t&)> visit;
        visit = [&](std::uint32_t start, std::uint32_t count, const Vec3& centre, double mean, double prio,
                    std::uint32_t& slot) {
            const bool fresh = slot == kNoSpec;  // computed now (each cluster's samples are settled once)
            if (fresh) {
                if (budget.fetch_sub(1, std::memory_order_relaxed) <= 0) return;
                const std::uint32_t s = alloc();
                specs[s] = Spec{split(start, count, centre, mean), {kNoSpec, kNoSpec}};
                work.fetch_add(count, std::memory_order_relaxed);
                const std::uint64_t m = made.fetch_add(1, std::memory_order_relaxed) + 1;
                if (progress && m % kProgressEvery == 0) {  // one round may be the whole tree: report within it
                    const std::lock_guard<std::mutex> lock(progress_mutex);
                    progress->splits_done({computed + m, settled.load(std::memory_order_relaxed), st.splits, work.load(std::memory_order_relaxed)});
                }
                slot = s;
            }
            Spec& sp = specs[slot];
            if (sp.r.skipped) {
                if (fresh) settled.fetch_add(count, std::memory_order_relaxed);
                return;
            }
            const std::uint32_t cnt[2] = {sp.r.behind, count - sp.r.behind};
            const std::uint32_t st0[2] = {start, start + sp.r.behind};
            bool go[2];
            double pr[2];
            for (int k = 0; k < 2; ++k) {
                pr[k] = std::min(prio, split_key(sp.r.child[k].error, cnt[k]));
                const bool splits = offerable(cnt[k], sp.r.child[k].error);
                if (!splits && fresh) settled.fetch_add(cnt[k], std::memory_order_relaxed);
                go[k] = splits && pr[k] >= tau;
            }
            auto child = [&](int k) {
                visit(st0[k], cnt[k], sp.r.child[k].centre, sp.r.child[k].mean_value, pr[k], sp.child_spec[k]);
            };
            if (go[0] && go[1])
                tbb::parallel_invoke([&] { child(0); }, [&] { child(1); });
            else if (go[0])
                child(0);
            else if (go[1])
                child(1);
        };
        // the heap holds exactly the queued clusters with priority >= tau
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, queue.size(), 1), [&](const tbb::blocked_range<std::size_t>& br) {
            for (std::size_t i = br.begin(); i != br.end(); ++i) {
                const QueueEntry& e = queue[i];
                visit(first[e.node], nodes[e.node].count, nodes[e.node].centre, mean_value[e.node], e.prio, spec_of[e.node]);
            }
        });
        free_specs.erase(free_specs.begin(), free_specs.begin() + std::min(free_specs.size(), next_free.load()));
        computed += made.load();
    };

    double growth = 1;       // splits a round made per queued cluster it started from (the last round's)
    std::size_t last_m = 1;  // the last round's m
    while (st.splits < params.max_splits) {
        if (queue.empty() || spec_of[queue.front().node] == kNoSpec) {
            // the heap is spent or its top (the next split in serial order) is not computed: a new
            // threshold tau, the tiers split at it, and a round if the top is not computed. tau is
            // -infinity when no split can be left out (max_splits at least all there can be);
            // otherwise the prio of the m-th worst queued cluster, m chosen so that the round makes
            // about half the splits left (at most most_splits / 2 kRoundsAtLeast) at the last
            // round's growth, and at most twice the last m
            if (queue.empty() && below.empty()) break;
            below.insert(below.end(), queue.begin(), queue.end());
            queue.clear();
            const std::uint64_t left = params.max_splits - st.splits;
            double tau = -std::numeric_limits<double>::infinity();
            auto mid = below.end();
            if (params.max_splits < n - 1) {
                const double want = 0.5 * static_cast<double>(std::min<std::uint64_t>(
                                              left, std::max<std::uint64_t>(most_splits / kRoundsAtLeast, 4096)));
                const std::size_t m = std::clamp<std::size_t>(static_cast<std::size_t>(want / growth), 1,
                                                              std::min(below.size(), 2 * last_m));
                last_m = m;
                // the m largest prios first; then the ties of the m-th from the rest (the heap's
                // pops do not depend on where its entries start: WorseFirst is a total order)
                const auto higher = [](const QueueEntry& a, const QueueEntry& b) { return a.prio > b.prio; };
                std::nth_element(below.begin(), below.begin() + static_cast<std::ptrdiff_t>(m - 1), below.end(), higher);
                tau = below[m - 1].prio;
                mid = std::partition(below.begin() + static_cast<std::ptrdiff_t>(m), below.end(),
                                     [&](const QueueEntry& q) { return q.prio >= tau; });
            }
            theta = tau;
            queue.assign(below.begin(), mid);
            below.erase(below.begin(), mid);
            std::make_heap(queue.begin(), queue.end(), WorseFirst{});
            if (spec_of[queue.front().node] != kNoSpec) continue;
            const std::uint64_t before = computed;
            expand_round(tau, static_cast<std::int64_t>(std::min(left, most_splits) + kPadSplits));
            growth = std::max(1.0, static_cast<double>(computed - before) / static_cast<double>(queue.size()));
            ++st.rounds;
            if (progress) progress->splits_done({computed, settled.load(std::memory_order_relaxed), st.splits, work.load(std::memory_order_relaxed)});
            continue;
        }
        const QueueEntry e = queue.front();
        const std::uint32_t s = spec_of[e.node];
        std::pop_heap(queue.begin(), queue.end(), WorseFirst{});
        queue.pop_back();
        const Spec& sp = specs[s];  // (specs grow only in rounds; the slot is reused only by the next)
        free_specs.push_back(s);
        if (sp.r.skipped) {
            nodes[e.node].flags |= kCbtSkippedSplit;
            ++st.skipped;
            continue;
        }
        const std::uint32_t start = first[e.node], count = nodes[e.node].count, depth = nodes[e.node].depth + 1;
        const std::uint32_t a = add_node(sp.r.child[0], start, sp.r.behind, depth);
        const std::uint32_t b = add_node(sp.r.child[1], start + sp.r.behind, count - sp.r.behind, depth);
        spec_of.push_back(sp.child_spec[0]);
        spec_of.push_back(sp.child_spec[1]);
        nodes[e.node].child = a;
        ++st.splits;
        if (progress && st.splits % kProgressEvery == 0) progress->splits_done({computed, settled.load(std::memory_order_relaxed), st.splits, work.load(std::memory_order_relaxed)});
        st.depth = std::max(st.depth, depth);
        offer(a, e.prio);
        offer(b, e.prio);
    }
    if (progress) progress->splits_done({computed, settled.load(std::memory_order_relaxed), st.splits, work.load(std::memory_order_relaxed)});
    st.speculative_unused = computed - st.splits - st.skipped;
    st.error_reached = 0;
    for (const CbtNode& d : nodes)
        if (d.leaf()) st.error_reached = std::max(st.error_reached, d.error);
    st.memory_bytes = idx.size() * 4 + nodes.size() * (sizeof(CbtNode) + 16) + specs.size() * sizeof(Spec);
    st.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return tree;
}

}  // namespace meshless
