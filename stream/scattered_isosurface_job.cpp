#include "stream/scattered_isosurface_job.hpp"

#include <sys/resource.h>

#include "formats/terminal_safe.hpp"
#include "stream/projection_meta.hpp"
#include "stream/scattered_isosurface_mpi.hpp"
#include "stream/scattered_store_ranks.hpp"
#include "stream/mpi_session.hpp"
#include "stream/seconds_since.hpp"
#include "stream/stencil_source.hpp"

namespace meshless {

namespace {

/// The stencils counted on j's progress (empty: none).
std::function<void(double)> stencil_progress(const IsosurfaceJob& j, const BinningGrid& grid) {
    return j.progress ? j.progress("stencils", static_cast<double>(StencilGrid(grid.dims).total())) : std::function<void(double)>();
}

/// j's outputs for a graph whose batches arrive already made (the MPI root, the slab runs).
std::size_t write_made_points(const IsosurfaceJob& j, const StreamMeta& meta, const std::function<void(Sink&)>& produce) {
    IsoSplatResult unused;
    return run_to_outputs(j.out, j.png, meta, j.rs, j.threads, [&](const Stage*, Sink& sink) {
        produce(sink);
        return IsoSplatResult{};
    }, unused, /*parallel_draw=*/false, /*with_blocks=*/false);
}

}  // namespace

std::size_t run_scattered_isosurface_job(const IsosurfaceJob& j, double dedup, const ScatteredIsosurfaceInput& in,
                                         IsosurfaceField& f, const char* cmd, std::FILE* warn) {
    if (dedup > 0) f.meta.set("dedup", dedup);
    ScatteredIsosurfaceStats st;
    IsoSplatResult unused;
    const auto t0 = std::chrono::steady_clock::now();
    const std::size_t points = run_to_outputs(j.out, j.png, f.meta, j.rs, j.threads, [&](const Stage* draw, Sink& sink) {
        const auto g0 = std::chrono::steady_clock::now();
        // --dedup: the removal runs in sequence order on the sink side (the picture is then drawn there too)
        if (!f.field.field) {
            st = run_scattered_isosurface(in, nullptr, j.iso, j.n, j.np, dedup, draw, sink, {j.threads});
        } else {
            // the stencils as the source hands them out, counted ahead of seeding
            st = run_scattered_isosurface(in, f.field.field.get(), j.iso, j.n, j.np, dedup, draw, sink, {j.threads},
                                          stencil_progress(j, in.grid));
        }
        IsoSplatResult r;
        r.seconds = seconds_since(g0);
        return r;
    }, unused, /*parallel_draw=*/dedup == 0, /*with_blocks=*/false);
    const double graph_seconds = seconds_since(t0);
    warn_if_unconverged(warn, in.source, st, f.name);
    if (j.stats)
        print_scattered_isosurface_stats(j.stats, cmd, in, st, j.n, f.name, j.np, dedup, points,
                                         {f.seconds, graph_seconds, seconds_since(j.started)}, j.threads);
    return points;
}

void run_scattered_isosurface_mpi_job(const IsosurfaceJob& j, double dedup, MpiSession& mpi, const ScatteredIsosurfaceInput& in,
                                      const IsosurfaceField& f, const char* cmd,
                                      const std::function<void(std::exception_ptr)>& on_deal_error) {
    const ScatteredMpiResult r = run_scattered_isosurface_mpi(
        mpi, in, f.field.field.get(), j.iso, j.n, j.np, dedup, j.threads,
        [&](const std::function<void(Sink&)>& produce) { return write_made_points(j, f.meta, produce); }, on_deal_error);
    if (mpi.rank() != 0 || !j.stats) return;
    print_scattered_ranks_stats(j.stats, cmd, in, r.totals, j.n, f.name, j.np, r.points, mpi.size(),
                                {f.seconds, 0, seconds_since(j.started)}, j.threads);
}

namespace {

/// The store's metadata as the slab runs write it.
StreamMeta store_meta(const IsosurfaceJob& j, double dedup, const ScatteredStorePlan& plan, const std::string& producer) {
    StreamMeta meta = scattered_store_meta(plan, j.iso, j.n, producer);
    widen_frame_for_travel(meta, j.np.seed_max_travel);
    add_projection_meta(meta, "mpu", j.np);
    if (dedup > 0) meta.set("dedup", dedup);
    return meta;
}

/// A budget near the least that runs makes many slabs that read the points several times over: said
/// (when the user gave the budget).
void warn_thin_slabs(std::FILE* warn, const char* cmd, const std::optional<std::string>& memory_option, const ScatteredStorePlan& plan,
                     const ScatteredStoreReport& rep) {
    if (memory_option && rep.slabs > 1 && rep.loaded > 4 * plan.frame.points)
        std::fprintf(warn, "meshless %s: warning: --memory %s made %d slabs that read the points %.0f times over; "
                           "more memory makes fewer, faster slabs\n",
                     cmd, terminal_safe(*memory_option).c_str(), rep.slabs,
                     static_cast<double>(rep.loaded) / static_cast<double>(plan.frame.points));
}

/// This process's peak resident memory in bytes (0 when unknown).
std::uint64_t peak_rss_bytes() {
    rusage ru{};
    if (getrusage(RUSAGE_SELF, &ru) != 0) return 0;
    return static_cast<std::uint64_t>(ru.ru_maxrss) * 1024;
}

}  // namespace

std::size_t run_scattered_store_mpi_job(const IsosurfaceJob& j, double dedup, MpiSession& mpi, const PointStore& store,
                                        const ScatteredStorePlan& plan, const FieldParams& field_params, const ScatteredStoreParams& sp,
                                        const std::string& producer, const std::optional<std::string>& memory_option, const char* cmd) {
    const StreamMeta meta = store_meta(j, dedup, plan, producer);
    const int rank = mpi.rank(), ranks = mpi.size();
    const auto t0 = std::chrono::steady_clock::now();
    StoreRankResult mine;
    std::size_t points = 0;
    std::optional<MpiChannel> channel;
    if (plan.crosses(j.iso)) channel.emplace(mpi);
    const auto run = [&](Sink* sink) {
        if (!channel) {  // (the isovalue crosses no data: rank 0 writes the empty output)
            if (sink) mine.stats = run_scattered_store_isosurface(store, plan, field_params, sp, j.iso, j.n, j.np, dedup, *sink, {j.threads});
            return;
        }
        const std::array<std::int64_t, 2> layers = store_layers_of_rank(plan, rank, ranks, store_slab_reach(plan, field_params, j.np));
        const double share = static_cast<double>((layers[1] - layers[0]) * StencilGrid(plan.grid.dims).count[0] *
                                                 StencilGrid(plan.grid.dims).count[1]);
        const auto progress = rank == 0 && j.progress ? j.progress("stencils", share) : std::function<void(double)>();
        mine = run_scattered_store_rank(store, plan, field_params, sp, j.iso, j.n, j.np, dedup, rank, ranks, *channel, sink, {j.threads},
                                        progress);
    };
    if (rank == 0)
        points = write_made_points(j, meta, [&](Sink& sink) { run(&sink); });
    else
        run(nullptr);
    if (channel) channel->flush();
    mine.peak_rss = peak_rss_bytes();
    std::vector<StoreRankShare> shares;
    const StoreRankResult tot = sum_store_rank_stats(mine, rank, ranks, [&mpi](const std::vector<std::int64_t>& v) { return mpi.sum_to_root(v); },
                                                     &shares);
    if (rank != 0) return points;
    warn_thin_slabs(stderr, cmd, memory_option, plan, tot.report);  // (the slabs of all ranks: each rank's budget)
    if (!j.stats) return points;
    print_store_isosurface_stats(j.stats, cmd, plan, tot.report, tot.stats, j.n, j.np, dedup, points,
                                 {0, seconds_since(t0), seconds_since(j.started)}, j.threads);
    std::fprintf(j.stats, "%s: over %d ranks, each its own stencil layers and the points they need:", cmd, ranks);
    for (int q = 0; q < ranks; ++q)
        std::fprintf(j.stats, "%s rank %d at most %llu points loaded, peak RSS %.1f MiB", q ? ";" : "", q,
                     static_cast<unsigned long long>(shares[static_cast<std::size_t>(q)].most_loaded),
                     static_cast<double>(shares[static_cast<std::size_t>(q)].peak_rss) / 1048576.0);
    std::fprintf(j.stats, "\n");
    return points;
}

std::size_t run_scattered_store_job(const IsosurfaceJob& j, double dedup, const PointStore& store, const ScatteredStorePlan& plan,
                                    const FieldParams& field_params, const ScatteredStoreParams& sp, const std::string& producer,
                                    const std::optional<std::string>& memory_option, const char* cmd, std::FILE* warn) {
    const StreamMeta meta = store_meta(j, dedup, plan, producer);
    ScatteredIsosurfaceStats st;
    ScatteredStoreReport rep;
    const auto t0 = std::chrono::steady_clock::now();
    const std::size_t points = write_made_points(j, meta, [&](Sink& sink) {
        st = run_scattered_store_isosurface(store, plan, field_params, sp, j.iso, j.n, j.np, dedup, sink, {j.threads},
                                            stencil_progress(j, plan.grid), &rep);
    });
    warn_thin_slabs(warn, cmd, memory_option, plan, rep);
    if (j.stats)
        print_store_isosurface_stats(j.stats, cmd, plan, rep, st, j.n, j.np, dedup, points, {0, seconds_since(t0), seconds_since(j.started)},
                                     j.threads);
    return points;
}

}  // namespace meshless
