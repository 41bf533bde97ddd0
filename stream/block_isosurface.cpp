#include "stream/block_isosurface.hpp"

#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <span>

#include "formats/multiblock_reader.hpp"
#include "kernels/amr_cover.hpp"
#include "kernels/barycentric_lattice.hpp"
#include "kernels/errors.hpp"
#include "stream/block_cell_source.hpp"
#include "stream/projection_meta.hpp"
#include "stream/record_vector_source.hpp"
#include "stream/stream_metadata.hpp"
#include "stream/seconds_since.hpp"

namespace meshless {

namespace {
using Clock = std::chrono::steady_clock;
}  // namespace

BlockIsosurfaceInput read_block_input(const std::vector<std::string>& paths, const PointSetOptions& options,
                                      const std::string& source, double iso) {
    const auto t0 = Clock::now();
    Multiblock mb = read_multiblock(paths, options);
    const double read_seconds = seconds_since(t0);
    if (mb.blocks.size() > std::numeric_limits<std::uint32_t>::max())
        throw FormatError(paths.at(0) + ": " + std::to_string(mb.blocks.size()) + " blocks, more than block ids can number");
    BlockIsosurfaceInput in = plan_block_isosurface(std::move(mb), source, iso);
    in.read_seconds = read_seconds;
    return in;
}

BlockIsosurfaceInput plan_block_isosurface(Multiblock mb, const std::string& source, double iso) {
    if (mb.blocks.size() > std::numeric_limits<std::uint32_t>::max())
        throw InvalidArgument(source + ": " + std::to_string(mb.blocks.size()) + " blocks, more than block ids can number");
    BlockIsosurfaceInput in;
    in.source = source;
    in.mb = std::move(mb);
    const auto t0 = Clock::now();
    if (has_cell_centred_blocks(in.mb)) in.padded = amr_seed_blocks(in.mb);
    in.plan = plan_block_seeds(in.seed_blocks(), iso);
    in.plan_seconds = seconds_since(t0);
    if (std::isnan(in.plan.value_range[0]))
        throw FormatError(in.source + ": every node is blanked or non-finite; there is no data to contour");
    return in;
}

StreamMeta block_isosurface_meta(const BlockIsosurfaceInput& in, double iso, int n, const std::string& producer) {
    StreamMeta m;
    m.set("source", in.source);
    m.set("iso", iso);
    m.set("blocks", std::to_string(in.mb.blocks.size()));
    m.set("samples", std::to_string(n));
    m.set("value_min", in.plan.value_range[0]);
    m.set("value_max", in.plan.value_range[1]);
    const auto& box = in.plan.active_cells > 0 ? in.plan.active_bounds : in.plan.node_bounds;
    m.set("bounds_lo", triple(box[0]));
    m.set("bounds_hi", triple(box[1]));
    m.set("volume_bounds_lo", triple(in.plan.node_bounds[0]));
    m.set("volume_bounds_hi", triple(in.plan.node_bounds[1]));
    m.set("producer", producer);
    return m;
}

BlockIsosurfaceStats run_block_isosurface(const BlockIsosurfaceInput& in, const Field* field, double iso, int n,
                                          const FieldProjectParams& np, const Stage* draw, Sink& sink, const RunOptions& opt,
                                          const std::function<void(double)>& progress) {
    BlockIsosurfaceStats st;
    if (!field) {
        EmptySource empty(Payload::points);
        const Stage* stages[] = {draw};
        run_pipeline(empty, std::span<const Stage* const>(stages, draw ? 1 : 0), sink, opt);
        st.seeds.cells = in.plan.total_cells();
        return st;
    }
    BlockCellSource source(in.plan.first_cell, block_seed_unit_cells(n));
    const BlockSeedStage seed(in.seed_blocks(), in.plan, iso, n);
    static_cast<SeedProjection&>(st) = run_seed_projection(source, seed, *field, iso, np, draw, sink, opt, progress);
    st.seeds = seed.stats();
    st.projected = true;
    return st;
}

BlockSeedStats generate_block_seeds(const BlockIsosurfaceInput& in, double iso, int n, Sink& sink, const RunOptions& opt) {
    BlockCellSource source(in.plan.first_cell, block_seed_unit_cells(n));
    const BlockSeedStage seed(in.seed_blocks(), in.plan, iso, n);
    const Stage* stages[] = {&seed};
    run_pipeline(source, stages, sink, opt);
    return seed.stats();
}

void print_block_seed_stats(std::FILE* out, const char* cmd, const BlockIsosurfaceInput& in, const BlockSeedStats& s, int n) {
    std::fprintf(out,
                 "%s: %zu blocks, %lld cells (skipped: %lld with an invalid corner, %lld collapsed/inverted, %lld covered by "
                 "a finer level), %lld active cells, %lld triangles (%lld of zero area skipped), %lld seeds (n = %d, %zu per "
                 "triangle)\n",
                 cmd, in.mb.blocks.size(), static_cast<long long>(s.cells), static_cast<long long>(s.invalid_cells),
                 static_cast<long long>(s.degenerate_cells), static_cast<long long>(s.covered_cells),
                 static_cast<long long>(s.active_cells),
                 static_cast<long long>(s.triangles), static_cast<long long>(s.zero_area_triangles),
                 static_cast<long long>(s.seeds), n, lattice_size(n));
}

void print_block_isosurface_stats(std::FILE* out, const char* cmd, const BlockIsosurfaceInput& in, const BlockIsosurfaceStats& st,
                                  int n, const std::string& field_name, const FieldProjectParams& np, std::size_t points,
                                  const IsosurfaceRunTimes& t, int threads) {
    print_block_seed_stats(out, cmd, in, st.seeds, n);
    if (st.projected) print_newton_stats(out, cmd, field_name, np, st.newton, st.newton_busy_seconds);
    std::fprintf(out,
                 "%s: %zu points; time: read %.3f s, plan %.3f s, field %.3f s, seeds + Newton + output %.3f s "
                 "(busy: seeds %.3f s, Newton %.3f s over %d thread(s)), total %.3f s\n",
                 cmd, points, in.read_seconds, in.plan_seconds, t.field, t.graph, st.seed_busy_seconds, st.newton_busy_seconds,
                 threads, t.total);
}

void print_block_generate_stats(std::FILE* out, const char* cmd, const BlockIsosurfaceInput& in, const BlockSeedStats& seeds, int n,
                                double total_seconds) {
    print_block_seed_stats(out, cmd, in, seeds, n);
    std::fprintf(out, "%s: read %.3f s, plan %.3f s, total %.3f s\n", cmd, in.read_seconds, in.plan_seconds, total_seconds);
}

IsosurfaceField fit_block_field(const BlockIsosurfaceInput& in, double iso, int n, const std::string& producer,
                                const FieldProjectParams& np, const std::string& kind,
                                const std::function<BuiltField(const PointSet&)>& build) {
    IsosurfaceField f;
    f.meta = block_isosurface_meta(in, iso, n, producer);
    const auto t0 = Clock::now();
    f.name = kind;
    if (in.plan.active_cells > 0) {
        f.field = build(to_point_set(in.mb));
        f.name = f.field.field->name();
    }
    f.seconds = seconds_since(t0);
    add_projection_meta(f.meta, f.name, np);
    return f;
}
}  // namespace meshless
