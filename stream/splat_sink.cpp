#include "stream/splat_sink.hpp"

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/enumerable_thread_specific.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <stdexcept>
#include <span>
#include <string>
#include <vector>

#include "kernels/errors.hpp"
#include "stream/large_page_allocator.hpp"
#include "stream/zeroed_buffer.hpp"
#include "stream/batch.hpp"

namespace meshless {

struct SplatSink::Canvas {
    LargeBuffer<std::uint64_t> keys;
    ZeroedBuffer<std::int64_t> acc;  // EWA pass 2: written only where fragments are accepted
    std::vector<PointRecord> batch;  // EWA pass 2: the spooled batch being replayed
    std::vector<std::uint32_t> blocks;  // ... and its block ids (when the spool has them)
    std::vector<EwaFootprint> footprints;   // EWA: the footprints of the batch spooled or replayed
    std::unique_ptr<FootprintSpool> spool;  // EWA without `replay`: this thread's footprints
    std::vector<SpoolGroup> groups;         // ... consecutive batches of it, in spool order
    std::uint64_t min_group = 0;            // ... each of at least this many footprints
    EwaCull cull;                           // EWA pass 1 from the spools: this key buffer's culling
    SplatStats stats;

    /// Notes count footprints appended to the spool at `first` with depths summing to depth_sum:
    /// they join the last group until it holds min_group; a thread with max_groups groups merges
    /// neighbours pairwise (consecutive in its spool) and doubles min_group, so memory is bounded.
    void add_group(std::uint64_t first, std::uint64_t count, double depth_sum, std::size_t max_groups) {
        if (!groups.empty() && groups.back().count < min_group) {
            groups.back().count += count;
            groups.back().depth_sum += depth_sum;
            return;
        }
        if (groups.size() == max_groups) {
            for (std::size_t i = 0; i < max_groups / 2; ++i) {
                SpoolGroup g = groups[2 * i];
                g.count += groups[2 * i + 1].count;
                g.depth_sum += groups[2 * i + 1].depth_sum;
                groups[i] = g;
            }
            groups.resize(max_groups / 2);
            min_group *= 2;
        }
        groups.push_back({spool.get(), first, count, depth_sum});
    }
};

struct SplatSink::Canvases {
    oneapi::tbb::enumerable_thread_specific<Canvas> per_thread;
    bool spool_footprints = false;
    std::uint64_t min_group = 4096;  // see SplatSink::set_spool_groups
    std::size_t max_groups = 1024;
    std::shared_ptr<SpoolMemory> spool_memory;  // the budget all the threads' spools share (set_spool_memory)
    Canvas& local(const SplatFrame& f) {
        Canvas& c = per_thread.local();
        if (spool_footprints && !c.spool) {
            c.spool = std::make_unique<FootprintSpool>("splat-spool", spool_memory);
            c.groups.reserve(max_groups);
            c.min_group = min_group;
        }
        if (!spool_footprints && c.keys.empty()) c.keys.assign(f.npix(), SplatFrame::kEmptyKey);
        return c;
    }
    /// A batch as it arrives. EWA with footprint spools: spools its footprints and notes their mean
    /// depth (finish() draws pass 1 from the spools, nearest groups first). Else draws it (quad, or
    /// EWA pass 1 when pass 2 replays a point spool).
    void draw(const SplatFrame& f, const Batch& b) {
        Canvas& c = local(f);
        if (!c.spool) {
            f.draw(b.points, c.keys.data(), c.stats, b.point_block);
            return;
        }
        f.footprints(b.points, c.footprints, b.point_block);
        if (c.footprints.empty()) return;
        double depth = 0;
        for (const EwaFootprint& fp : c.footprints) depth += fp.depth;
        c.add_group(c.spool->size(), c.footprints.size(), depth, max_groups);
        c.spool->append(c.footprints);
    }
};

namespace {
void require_points(const Batch& b, const ShadingParams& sh) {
    if (sh.color_by == ColorBy::block && !b.points.empty() && b.point_block.size() != b.points.size())
        throw FormatError("splat: colouring by block (--color block), but the points carry no block ids");
}
}  // namespace

class SplatSink::DrawStage final : public Stage {
public:
    PayloadSet takes() const override { return Payload::points; }
    Payload gives(Payload) const override { return Payload::points; }
    explicit DrawStage(SplatSink& s) : s_(s) {}
    void process(Batch& b) const override {
        require_points(b, s_.shading_);
        s_.canvases_->draw(s_.frame_, b);
    }

private:
    SplatSink& s_;
};

SplatSink::SplatSink(const Camera& cam, SplatKernel kernel, const ShadingParams& shading,
                     const std::array<Vec3, 2>& bounds, int threads, const PointSpool* replay)
    : frame_(cam, kernel, shading, bounds), shading_(shading), threads_(std::max(threads, 1)), canvases_(std::make_unique<Canvases>()) {
    canvases_->spool_memory = std::make_shared<SpoolMemory>(kSpoolMemory);
    if (!frame_.two_pass()) return;
    pass2_ = replay;
    // Without a replay spool, pass 1 spools footprints (one file per drawing thread); this thread's
    // is made now, so that an unusable temporary directory fails before the first point.
    canvases_->spool_footprints = replay == nullptr;
    if (!replay) canvases_->local(frame_);
}

SplatSink::~SplatSink() = default;

void SplatSink::set_spool_memory(std::size_t bytes) {
    bool started = points_ != 0;  // (a staged draw spools before observe() counts)
    for (const Canvas& c : canvases_->per_thread) started = started || (c.spool && c.spool->size() > 0);
    if (started) throw std::logic_error("SplatSink::set_spool_memory: before any point");
    if (bytes == canvases_->spool_memory->total()) return;
    canvases_->spool_memory = std::make_shared<SpoolMemory>(bytes);
    // this thread's spool was made by the constructor (to fail early): remade empty with the new budget
    for (Canvas& c : canvases_->per_thread)
        if (c.spool) c.spool = std::make_unique<FootprintSpool>("splat-spool", canvases_->spool_memory);
}

void SplatSink::set_spool_groups(std::uint64_t min_group, std::size_t max_groups) {
    if (min_group < 1 || max_groups < 2 || max_groups % 2 != 0 || points_ != 0)
        throw std::logic_error("SplatSink::set_spool_groups: min_group >= 1, max_groups even and >= 2, before any point");
    canvases_->min_group = min_group;
    canvases_->max_groups = max_groups;
    for (Canvas& c : canvases_->per_thread) {
        c.min_group = min_group;
        c.groups.reserve(max_groups);
    }
}

const Stage& SplatSink::stage() {
    if (!stage_) stage_ = std::make_unique<DrawStage>(*this);
    staged_ = true;
    return *stage_;
}

void SplatSink::observe(const Batch& b) {
    require_points(b, shading_);
    points_ += b.points.size();
    if (!staged_) canvases_->draw(frame_, b);
}

void SplatSink::finish() {
    const auto t0 = std::chrono::steady_clock::now();
    const std::size_t npix = frame_.npix();
    std::vector<std::unique_ptr<FootprintSpool>> spools;  // the footprints, one spool per thread
    std::vector<SpoolGroup> groups;
    for (Canvas& c : canvases_->per_thread) {
        if (!c.spool) continue;
        c.spool->flush();
        spools.push_back(std::move(c.spool));
        groups.insert(groups.end(), c.groups.begin(), c.groups.end());
        c.groups.clear();
    }
    if (!spools.empty()) {
        // EWA pass 1 from the spools, nearest groups first, so that most splats hidden behind
        // nearer ones are culled (EwaCull); the keys are a minimum, so the order changes no byte.
        std::stable_sort(groups.begin(), groups.end(),
                         [](const SpoolGroup& a, const SpoolGroup& b) { return a.mean_depth() < b.mean_depth(); });
        // each thread takes the nearest group left, so every key buffer fills front to back
        std::atomic<std::size_t> next{0};
        run_parts(static_cast<std::size_t>(threads_), [&](std::size_t) {
            for (std::size_t i; (i = next.fetch_add(1, std::memory_order_relaxed)) < groups.size();) {
                Canvas& c = canvases_->per_thread.local();
                if (c.keys.empty()) c.keys.assign(npix, SplatFrame::kEmptyKey);
                const SpoolGroup& g = groups[i];
                g.spool->visit(g.first, g.count, c.footprints, [&](std::span<const EwaFootprint> part) {
                    frame_.draw(part, c.keys.data(), c.stats, &c.cull);
                });
            }
        });
    }
    // Merge the partial visibility / colour buffers by min.
    LargeBuffer<std::uint64_t> keys;
    for (Canvas& c : canvases_->per_thread) {
        stats_.splats_drawn += c.stats.splats_drawn;
        stats_.fragments += c.stats.fragments;
        c.stats = {};
        if (c.keys.empty()) continue;
        if (keys.empty()) keys = std::move(c.keys);
        else SplatFrame::merge_keys(keys.data(), c.keys.data(), npix);
        c.keys = {};
        c.keys.shrink_to_fit();
    }
    if (keys.empty()) keys.assign(npix, SplatFrame::kEmptyKey);
    canvases_->per_thread.clear();

    ZeroedBuffer<std::int64_t> acc;
    if (frame_.two_pass()) {
        const std::size_t words = frame_.acc_words();
        const VisibleDepthTiles tiles = frame_.depth_tiles(keys.data());
        // Pass 2 replays the spools in batches; each task reads its own batch (pread), so threads
        // meet only at the end, and memory is one batch + one accumulator per thread.
        struct Part {
            const FootprintSpool* spool;  // null: the replay spool's points
            std::uint64_t first, count;
        };
        std::vector<Part> parts;
        if (pass2_) {
            if (pass2_->size() != points_)
                throw std::logic_error("SplatSink: the replay spool holds " + std::to_string(pass2_->size()) +
                                       " points, the sink was given " + std::to_string(points_));
            if (shading_.color_by == ColorBy::block && points_ > 0 && !pass2_->has_blocks())
                throw FormatError("splat: colouring by block (--color block), but the spooled points carry no block ids");
            for (std::uint64_t first = 0; first < points_; first += kMaxBatchRecords)
                parts.push_back({nullptr, first, std::min<std::uint64_t>(kMaxBatchRecords, points_ - first)});
        } else {
            for (const auto& sp : spools) {
                for (std::uint64_t first = 0; first < sp->size(); first += kMaxBatchRecords)
                    parts.push_back({sp.get(), first, std::min<std::uint64_t>(kMaxBatchRecords, sp->size() - first)});
            }
        }
        const bool with_blocks = shading_.color_by == ColorBy::block;
        oneapi::tbb::enumerable_thread_specific<Canvas> accs;
        auto replay = [&](std::size_t i) {
            Canvas& c = accs.local();
            if (c.acc.empty()) c.acc = ZeroedBuffer<std::int64_t>(words * npix);
            const Part& p = parts[i];
            if (p.spool) {
                p.spool->visit(p.first, p.count, c.footprints, [&](std::span<const EwaFootprint> part) {
                    frame_.accumulate(part, keys.data(), c.acc.data(), c.stats, &tiles);
                });
                return;
            }
            c.batch.resize(static_cast<std::size_t>(p.count));
            pass2_->read(p.first, c.batch);
            c.blocks.clear();
            if (with_blocks) {
                c.blocks.resize(c.batch.size());
                pass2_->read_blocks(p.first, c.blocks);
            }
            frame_.accumulate(c.batch, keys.data(), c.acc.data(), c.stats, c.blocks, &tiles);
        };
        run_parts(parts.size(), replay);
        for (Canvas& c : accs) {
            stats_.fragments += c.stats.fragments;
            if (c.acc.empty()) continue;
            if (acc.empty()) acc = std::move(c.acc);
            else SplatFrame::merge_acc(acc.data(), c.acc.data(), words * npix);
            c.acc = {};
        }
        if (acc.empty()) acc = ZeroedBuffer<std::int64_t>(words * npix);
    }
    frame_.resolve(keys.data(), acc.data(), image_);
    stats_.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

template <class Fn>
void SplatSink::run_parts(std::size_t n, Fn&& fn) const {
    if (threads_ == 1) {
        for (std::size_t i = 0; i < n; ++i) fn(i);
        return;
    }
    oneapi::tbb::task_arena arena(threads_);
    arena.execute([&] {
        oneapi::tbb::parallel_for(oneapi::tbb::blocked_range<std::size_t>(0, n, 1),
                                  [&](const oneapi::tbb::blocked_range<std::size_t>& r) {
                                      for (std::size_t i = r.begin(); i != r.end(); ++i) fn(i);
                                  });
    });
}

std::size_t SplatSink::retained_bytes() const {
    std::size_t n = image_.rgb.capacity();
    for (const Canvas& c : canvases_->per_thread)
        n += c.keys.capacity() * sizeof(std::uint64_t) + c.acc.bytes() +
             c.footprints.capacity() * sizeof(EwaFootprint) + c.groups.capacity() * sizeof(SpoolGroup) +
             (c.spool ? c.spool->memory_bytes() : 0);
    return n;
}

}  // namespace meshless
