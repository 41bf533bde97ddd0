#include "stream/scattered_store_isosurface.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <optional>

#include "kernels/binning_rule_scan.hpp"
#include "kernels/errors.hpp"
#include "kernels/marching_stencils.hpp"
#include "kernels/mpu_field.hpp"
#include "kernels/mpu_fit_cache.hpp"
#include "stream/dedup_sink.hpp"
#include "stream/stencil_seed_stage.hpp"
#include "stream/stencil_source.hpp"
#include "stream/store_slab.hpp"
#include "stream/seconds_since.hpp"

namespace meshless {

namespace {

using Clock = std::chrono::steady_clock;
constexpr double kInf = std::numeric_limits<double>::infinity();

/// Every point of the store, brick by brick, in store order (the order the in-memory path reads).
void scan_store(const PointStore& store, const std::function<void(std::span<const Vec3>, std::span<const double>)>& visit) {
    std::vector<double> raw;
    std::vector<Vec3> pos;
    std::vector<double> val;
    for (std::size_t i = 0; i < store.bricks().size(); ++i) {
        store.read_brick(i, raw);
        pos.resize(raw.size() / 4);
        val.resize(raw.size() / 4);
        for (std::size_t k = 0; k < pos.size(); ++k) {
            pos[k] = Vec3{raw[4 * k], raw[4 * k + 1], raw[4 * k + 2]};
            val[k] = raw[4 * k + 3];
        }
        visit(pos, val);
    }
}

class SlabPlanner {
public:
    SlabPlanner(const PointStore& store, const ScatteredStorePlan& plan, double pad)
        : store_(store), plan_(plan), sg_(plan.grid.dims), pad_(pad) {}
    std::int64_t layers() const { return sg_.count[2]; }
    std::int64_t stencils_per_layer() const { return sg_.count[0] * sg_.count[1]; }
    // The lowest world z where the field of stencil layers [s0, ...) is evaluated.
    double query_from(std::int64_t s0) const { return plan_.grid.origin.z + static_cast<double>(2 * s0 - 1) * plan_.grid.cell.z - pad_; }
    // Stencil layers [s0, s1) with a halo of `halo` world units along z, and the bricks `extra` flags.
    StoreSlab slab(std::int64_t s0, std::int64_t s1, double halo, const std::vector<char>& extra) const {
        const BinningGrid& g = plan_.grid;
        // the regularised block reaches one cell beyond the stencils' cells (kernels/stencil_seeds.cpp)
        const std::int64_t k1 = stencil_centre(s1 - 1, g.dims[2]) + 3;  // (and k0 = 2 s0 - 1: query_from)
        return store_slab(store_, plan_, {query_from(s0), g.origin.z + static_cast<double>(k1) * g.cell.z + pad_}, halo, extra);
    }
    /// The x-y extent of every slab's queries: the grid, padded by Newton's reach.
    std::array<Vec3, 2> query_xy() const {
        const BinningGrid& g = plan_.grid;
        return {Vec3{g.origin.x - pad_, g.origin.y - pad_, 0},
                Vec3{g.origin.x + static_cast<double>(g.dims[0]) * g.cell.x + pad_, g.origin.y + static_cast<double>(g.dims[1]) * g.cell.y + pad_, 0}};
    }

private:
    const PointStore& store_;
    const ScatteredStorePlan& plan_;
    StencilGrid sg_;
    double pad_;
};

void add_seed_stats(StencilSeedStats& to, const StencilSeedStats& s) {
    auto a = to.as_array();
    const auto b = s.as_array();
    for (std::size_t i = 0; i < a.size(); ++i)
        a[i] = i == StencilSeedStats::kMaxIndex ? std::max(a[i], b[i]) : a[i] + b[i];
    to = StencilSeedStats::from_array(a);
}


std::string mib(double bytes) {
    char b[64];
    std::snprintf(b, sizeof b, "%.0f MiB", std::ceil(bytes / 1048576.0));
    return b;
}

}  // namespace

namespace {
ScatteredStorePlan plan_store(const PointStore& store, const std::string& source, const BinningGridParams& bp, const InputWarning& warn,
                              std::optional<int> level);
}  // namespace

ScatteredStorePlan plan_scattered_store(const PointStore& store, const std::string& source, const BinningGridParams& bp,
                                        const InputWarning& warn) {
    return plan_store(store, source, bp, warn, std::nullopt);
}

ScatteredStorePlan plan_store_field(const PointStore& store, const std::string& source, int level) {
    if (level < 0 || level > 10) throw InvalidArgument("plan_store_field: level " + std::to_string(level) + " outside 0..10");
    return plan_store(store, source, BinningGridParams{}, InputWarning{}, level);
}

namespace {
ScatteredStorePlan plan_store(const PointStore& store, const std::string& source, const BinningGridParams& bp, const InputWarning& warn,
                              std::optional<int> level) {
    const auto t0 = Clock::now();
    ScatteredStorePlan plan;
    plan.source = source;
    plan.dropped_nonfinite = store.info().dropped_nonfinite;
    if (warn && plan.dropped_nonfinite > 0)
        warn(store.path(), std::to_string(plan.dropped_nonfinite) + " points with a NaN/Inf position or value dropped");
    // scan 1: the frame (the bits the in-memory field computes over the same order) and the values
    FieldFrameBuilder fb;
    double vmin = kInf, vmax = -kInf;
    scan_store(store, [&](std::span<const Vec3> pos, std::span<const double> val) {
        fb.add(pos);
        for (double v : val) vmin = std::min(vmin, v), vmax = std::max(vmax, v);
    });
    plan.frame = fb.finish();
    plan.value_range = {vmin, vmax};
    const Vec3 ext = plan.frame.bounds[1] - plan.frame.bounds[0];
    if (plan.frame.points < 4 || !(std::max({ext.x, ext.y, ext.z}) > 0))
        throw FormatError(store.path() + ": fewer than 4 distinct point positions; a volume needs at least 4 points not all in one place");
    // the binning rule, one scan per level it descends
    int scans = 0;
    const PointScan positions = [&](const std::function<void(std::span<const Vec3>)>& chunk) {
        scan_store(store, [&](std::span<const Vec3> pos, std::span<const double>) { chunk(pos); });
    };
    plan.grid = binning_grid_of(plan.frame.bounds,
                                level ? *level : binning_rule_level_scanned(positions, plan.frame.points, plan.frame.bounds, bp, &scans), bp);
    // last scan: the points of every cell (the statistics, the largest stencil, the layer counts)
    BinnedPoints counts;
    counts.start.assign(static_cast<std::size_t>(plan.grid.cell_count()) + 1, 0);
    positions([&](std::span<const Vec3> pos) {
        for (const Vec3& p : pos) {
            const auto c = plan.grid.cell_of(p);
            ++counts.start[static_cast<std::size_t>(plan.grid.index(c[0], c[1], c[2])) + 1];
        }
    });
    plan.scans = scans + 2;
    const BinningGrid& g = plan.grid;
    plan.layer_points.assign(static_cast<std::size_t>(g.dims[2]), 0);
    for (std::int64_t c = 0; c < g.cell_count(); ++c) {
        const std::uint32_t n = counts.start[static_cast<std::size_t>(c) + 1];
        const std::int64_t k = c / (g.dims[0] * g.dims[1]), j = (c / g.dims[0]) % g.dims[1], i = c % g.dims[0];
        plan.layer_points[static_cast<std::size_t>(k)] += n;
        if (n == 0) {
            ++plan.empty_cells;
            const bool border = i == 0 || j == 0 || k == 0 || i == g.dims[0] - 1 || j == g.dims[1] - 1 || k == g.dims[2] - 1;
            if (!border) ++plan.empty_interior_cells;
        }
        plan.max_per_cell = std::max(plan.max_per_cell, n);
        counts.start[static_cast<std::size_t>(c) + 1] += counts.start[static_cast<std::size_t>(c)];
    }
    counts.empty_cells = plan.empty_cells;
    counts.empty_interior_cells = plan.empty_interior_cells;
    counts.max_per_cell = plan.max_per_cell;
    plan.largest_stencil = largest_stencil_points(g, counts);
    // the summed-area table: T(i, j, k) = the points of cells [0, i) x [0, j) x [0, k)
    const std::int64_t tx = g.dims[0] + 1, ty = g.dims[1] + 1, tz = g.dims[2] + 1;
    plan.cell_table.assign(static_cast<std::size_t>(tx * ty * tz), 0);
    const auto at = [&](std::int64_t i, std::int64_t j, std::int64_t k) -> std::uint32_t& {
        return plan.cell_table[static_cast<std::size_t>(i + tx * (j + ty * k))];
    };
    for (std::int64_t k = 1; k < tz; ++k)
        for (std::int64_t j = 1; j < ty; ++j)
            for (std::int64_t i = 1; i < tx; ++i) {
                const std::size_t c = static_cast<std::size_t>(g.index(i - 1, j - 1, k - 1));
                const std::uint32_t n = counts.start[c + 1] - counts.start[c];
                at(i, j, k) = n + at(i - 1, j, k) + at(i, j - 1, k) + at(i, j, k - 1) - at(i - 1, j - 1, k) - at(i - 1, j, k - 1) -
                              at(i, j - 1, k - 1) + at(i - 1, j - 1, k - 1);
            }
    if (warn) warn_about_binning(g, plan.largest_stencil, plan.frame.points, store.path(), bp, warn);
    plan.seconds = seconds_since(t0);
    return plan;
}
}  // namespace

std::uint64_t ScatteredStorePlan::points_in_cells(std::array<std::int64_t, 3> lo, std::array<std::int64_t, 3> hi) const {
    for (std::size_t a = 0; a < 3; ++a) {
        lo[a] = std::max<std::int64_t>(lo[a], 0);
        hi[a] = std::min<std::int64_t>(hi[a], grid.dims[a] - 1);
        if (lo[a] > hi[a]) return 0;
    }
    const std::int64_t tx = grid.dims[0] + 1, ty = grid.dims[1] + 1;
    const auto t = [&](std::int64_t i, std::int64_t j, std::int64_t k) {
        return static_cast<std::int64_t>(cell_table[static_cast<std::size_t>(i + tx * (j + ty * k))]);
    };
    const std::int64_t i0 = lo[0], j0 = lo[1], k0 = lo[2], i1 = hi[0] + 1, j1 = hi[1] + 1, k1 = hi[2] + 1;
    return static_cast<std::uint64_t>(t(i1, j1, k1) - t(i0, j1, k1) - t(i1, j0, k1) - t(i1, j1, k0) + t(i0, j0, k1) + t(i0, j1, k0) +
                                      t(i1, j0, k0) - t(i0, j0, k0));
}

namespace {

// The cells of row (j, k) whose closed box meets (inner: lies inside) the ball (c, r), as an
// index range [i0, i1] (i0 > i1: none).
std::array<std::int64_t, 2> row_cells(const BinningGrid& g, std::int64_t j, std::int64_t k, const Vec3& c, double r, bool inner) {
    // the distance from c to the row's y-z rectangle: nearest point (meets), farthest corner (inside)
    const auto axis = [&](int a, std::int64_t idx) {
        const double lo = g.origin[a] + static_cast<double>(idx) * g.cell[a], hi = lo + g.cell[a];
        if (inner) return std::max(std::abs(c[a] - lo), std::abs(c[a] - hi));
        return c[a] < lo ? lo - c[a] : (c[a] > hi ? c[a] - hi : 0.0);
    };
    const double dy = axis(1, j), dz = axis(2, k);
    const double rest = r * r - dy * dy - dz * dz;
    if (rest < 0) return {1, 0};
    const double h = std::sqrt(rest);
    const double u0 = (c.x - h - g.origin.x) / g.cell.x, u1 = (c.x + h - g.origin.x) / g.cell.x;
    const double top = static_cast<double>(g.dims[0]);
    if (inner)  // cells [i, i + 1] inside [u0, u1]
        return {static_cast<std::int64_t>(std::clamp(std::ceil(u0), 0.0, top)), static_cast<std::int64_t>(std::clamp(std::floor(u1) - 1, -1.0, top - 1))};
    return {static_cast<std::int64_t>(std::clamp(std::floor(u0), 0.0, top)), static_cast<std::int64_t>(std::clamp(std::floor(u1), -1.0, top - 1))};
}

std::array<std::int64_t, 2> cell_span(const BinningGrid& g, int a, double lo, double hi) {
    const double top = static_cast<double>(g.dims[static_cast<std::size_t>(a)]);
    return {static_cast<std::int64_t>(std::clamp(std::floor((lo - g.origin[a]) / g.cell[a]), 0.0, top)),
            static_cast<std::int64_t>(std::clamp(std::floor((hi - g.origin[a]) / g.cell[a]), -1.0, top - 1))};
}

}  // namespace

std::uint64_t ScatteredStorePlan::points_near(const Vec3& c, double r, const std::array<double, 2>& loaded_z) const {
    const BinningGrid& g = grid;
    const auto ys = cell_span(g, 1, c.y - r, c.y + r), zs = cell_span(g, 2, c.z - r, c.z + r);
    std::uint64_t n = 0;
    for (std::int64_t k = zs[0]; k <= zs[1]; ++k) {
        // a layer whose cells lie wholly inside the loaded z range has every point loaded (a
        // point's cell holds it: cell_of only clamps points on the grid's faces inward)
        const double z0 = g.origin.z + static_cast<double>(k) * g.cell.z, z1 = z0 + g.cell.z;
        if (z0 > loaded_z[0] && z1 < loaded_z[1]) continue;
        for (std::int64_t j = ys[0]; j <= ys[1]; ++j) {
            const auto is = row_cells(g, j, k, c, r, false);
            if (is[0] <= is[1]) n += points_in_cells({is[0], j, k}, {is[1], j, k});
        }
    }
    return n;
}

std::uint64_t ScatteredStorePlan::points_surely_in(const Vec3& c, double r) const {
    const BinningGrid& g = grid;
    const auto ys = cell_span(g, 1, c.y - r, c.y + r), zs = cell_span(g, 2, c.z - r, c.z + r);
    std::uint64_t n = 0;
    for (std::int64_t k = zs[0]; k <= zs[1]; ++k)
        for (std::int64_t j = ys[0]; j <= ys[1]; ++j) {
            const auto is = row_cells(g, j, k, c, r, true);
            if (is[0] <= is[1]) n += points_in_cells({is[0], j, k}, {is[1], j, k});
        }
    return n;
}

StreamMeta scattered_store_meta(const ScatteredStorePlan& plan, double iso, int n, const std::string& producer) {
    return scattered_isosurface_meta(plan.grid, plan.frame.points, plan.value_range, plan.source, iso, n, producer);
}

namespace {

/// Newton's reach from a seed (max travel cell diagonals), one diagonal more for a last trial step.
double newton_pad(double diag, const FieldProjectParams& np) { return (np.seed_max_travel + 1) * diag * (1 + 1e-6); }

/// Adds a slab's seeding and Newton figures to the run's.
void add_slab_stats(ScatteredIsosurfaceStats& st, const ScatteredIsosurfaceStats& part) {
    st.newton += part.newton;
    st.seed_busy_seconds += part.seed_busy_seconds;
    st.newton_busy_seconds += part.newton_busy_seconds;
    add_seed_stats(st.seeds, part.seeds);
}

}  // namespace

double store_slab_reach(const ScatteredStorePlan& plan, const FieldParams& field_params, const FieldProjectParams& np) {
    return newton_pad(plan.grid.diagonal(), np) + store_first_halo(plan, field_params);
}

std::uint64_t store_layers_loaded(const ScatteredStorePlan& plan, std::int64_t s0, std::int64_t s1, double reach) {
    const BinningGrid& g = plan.grid;
    if (s1 <= s0) return 0;
    // the z range a slab of stencil layers [s0, s1) loads (SlabPlanner::slab), and the cell layers meeting it
    const double lo = g.origin.z + static_cast<double>(2 * s0 - 1) * g.cell.z - reach;
    const double hi = g.origin.z + static_cast<double>(stencil_centre(s1 - 1, g.dims[2]) + 3) * g.cell.z + reach;
    const auto k0 = static_cast<std::int64_t>(std::max(0.0, std::ceil((lo - g.origin.z) / g.cell.z - 1)));
    const auto k1 = std::min<std::int64_t>(g.dims[2] - 1, static_cast<std::int64_t>(std::floor((hi - g.origin.z) / g.cell.z)));
    std::uint64_t n = 0;
    for (std::int64_t k = k0; k <= k1; ++k) n += plan.layer_points[static_cast<std::size_t>(k)];
    return n;
}

namespace {

/// The slab's points loaded and binned on the plan's grid, counted in the report.
ScatteredIsosurfaceInput slab_input(const PointStore& store, const ScatteredStorePlan& plan, const StoreSlab& slab, double reg_gap,
                                    ScatteredStoreReport& rep) {
    ScatteredIsosurfaceInput in;
    in.source = plan.source;
    in.points = load_store_slab(store, slab, rep.read_seconds);
    in.grid = plan.grid;
    in.bins = bin_points(plan.grid, in.points.pos);
    in.reg_gap = reg_gap;
    rep.loaded += in.points.size();
    rep.most_loaded = std::max<std::uint64_t>(rep.most_loaded, in.points.size());
    return in;
}

/// The refusal of a budget too small for one stencil layer's field (`need` bytes for `loaded`
/// points, `others` beside it), with what would do: the fullest layer of the store (its points grown
/// as this one's grew with the lacking balls), at this field's bytes a point.
InvalidArgument budget_too_small(const PointStore& store, const SlabPlanner& planner, std::int64_t s0, double halo0,
                                 std::size_t loaded, double need, double others, double fixed, const ScatteredStoreParams& sp) {
    const std::vector<char> no_extra(store.bricks().size(), 0);
    const double base = static_cast<double>(std::max<std::uint64_t>(1, planner.slab(s0, s0 + 1, halo0, no_extra).points));
    const double grown = std::max(1.0, static_cast<double>(loaded) / base);
    std::uint64_t most = 0;
    for (std::int64_t k = 0; k < planner.layers(); ++k) most = std::max(most, planner.slab(k, k + 1, halo0, no_extra).points);
    const double per = 1.1 * need / static_cast<double>(loaded) + sp.other_bytes_per_point;
    const double would = 1.1 * std::max(need + others, static_cast<double>(most) * grown * per) + fixed;
    return InvalidArgument("--memory " + mib(static_cast<double>(sp.memory_bytes)) + " is too small for this store: the field of one " +
                           "stencil layer of the binning grid (" + std::to_string(loaded) + " points with its halo) takes " + mib(need) +
                           "; the fullest layer needs about --memory " + mib(would));
}

/// A slab whose field would not fit its share of the budget: fewer layers, as many as the field's
/// size allows (`room`: the share over the field's bytes), or, at one layer, no fits kept from the
/// slab before. False when neither is left.
bool fewer_layers_or_no_kept_fits(std::int64_t s0, std::int64_t& s1, MpuFitCache& cache, double room) {
    if (s1 > s0 + 1) {
        s1 = std::min(s1 - 1, s0 + std::max<std::int64_t>(1, static_cast<std::int64_t>(static_cast<double>(s1 - s0) * room * 0.95)));
        return true;
    }
    if (cache.bytes() > 0) {  // (this slab fits again what it overlaps)
        cache.clear();
        return true;
    }
    return false;
}

/// What runs slab by slab: the mpu field (InvalidArgument otherwise) with a limited Newton travel.
void check_slab_run(const FieldParams& field_params, const FieldProjectParams& np) {
    if (field_params.kind != FieldKind::mpu) throw InvalidArgument("a point store runs slab by slab with the mpu field only");
    if (!std::isfinite(np.seed_max_travel))
        throw InvalidArgument("a point store runs slab by slab only with a limited Newton travel (--max-travel > 0)");
}

/// A finished slab's figures added to the run's: its seeding and Newton steps, its field, its halo (cells).
void record_slab(ScatteredIsosurfaceStats& st, ScatteredStoreReport& rep, const ScatteredIsosurfaceStats& part,
                 const FieldBuildStats& fst, double halo_cells) {
    add_slab_stats(st, part);
    add_slab_field_stats(rep.field, fst);
    rep.halo_cells = std::max(rep.halo_cells, halo_cells);
    ++rep.slabs;
}

}  // namespace

ScatteredIsosurfaceStats run_scattered_store_isosurface(const PointStore& store, const ScatteredStorePlan& plan,
                                                        const FieldParams& field_params, const ScatteredStoreParams& sp,
                                                        double iso, int n, const FieldProjectParams& np, double dedup,
                                                        Sink& out, const RunOptions& opt,
                                                        const std::function<void(double)>& progress,
                                                        ScatteredStoreReport* report) {
    check_slab_run(field_params, np);
    ScatteredStoreReport rep;
    ScatteredIsosurfaceStats st;
    std::optional<DedupSink> dedup_sink;
    if (dedup > 0) dedup_sink.emplace(out, dedup, 0.1 * plan.grid.diagonal());
    Sink& sink = dedup_sink ? static_cast<Sink&>(*dedup_sink) : out;
    if (!plan.crosses(iso)) {
        sink.finish();
        if (report) *report = rep;
        return st;
    }
    const BinningGrid& g = plan.grid;
    const double diag = g.diagonal();
    // Newton's reach from a seed (max travel cell diagonals), one diagonal more for a last trial step
    const double pad = newton_pad(diag, np);
    const SlabPlanner planner(store, plan, pad);
    const StoreBrickIndex index(store);
    const double fixed = 8.0 * static_cast<double>(g.cell_count());  // the bins' index, and slack for the counts
    const double budget = static_cast<double>(sp.memory_bytes) - fixed;
    // the fits kept for the next slab: those of the last slab, and the current one's as it keeps them (about as many)
    MpuFitCache cache;
    // bytes a loaded point: the first guess until a field shows its own (the most a point took so far)
    double field_per_point = 0;
    const auto per_point = [&] { return field_per_point > 0 ? 1.1 * field_per_point + sp.other_bytes_per_point : sp.bytes_per_point; };
    const auto fits = [&](const StoreSlab& s) { return static_cast<double>(s.points) * per_point() + 2.0 * static_cast<double>(cache.bytes()) <= budget; };
    std::uint64_t seq = 0;
    const double halo0 = store_first_halo(plan, field_params);
    std::vector<std::pair<Vec3, double>> seen;  // the lacking balls of the slabs so far
    const std::int64_t first = std::clamp<std::int64_t>(sp.layers[0], 0, planner.layers());
    const std::int64_t end = sp.layers[1] < 0 ? planner.layers() : std::clamp<std::int64_t>(sp.layers[1], first, planner.layers());
    for (std::int64_t s0 = first; s0 < end;) {
        double halo = halo0;
        // bricks that lacking balls asked for
        std::vector<char> extra = bricks_still_lacking(store, index, seen, planner.query_from(s0) - halo0);
        std::int64_t s1 = s0 + 1;
        while (s1 < end && fits(planner.slab(s0, s1 + 1, halo, extra))) ++s1;
        for (;;) {
            const StoreSlab slab = planner.slab(s0, s1, halo, extra);
            if (!fits(slab) && s1 > s0 + 1) {  // (one layer is tried whatever the guess: its octree will tell)
                --s1;
                continue;
            }
            ScatteredIsosurfaceInput in = slab_input(store, plan, slab, sp.reg_gap, rep);
            StoreSlabRegion slab_region(store, plan, index, slab, planner.query_xy());
            FieldRegion& region = slab_region.region;
            const double others = static_cast<double>(in.points.size()) * sp.other_bytes_per_point + 2.0 * static_cast<double>(cache.bytes());
            region.max_field_bytes = static_cast<std::uint64_t>(std::max(1.0, budget - others));
            FieldBuildStats fst;
            std::unique_ptr<MpuField> field;
            rep.field_seconds += build_alongside_coverage(in, opt.threads, [&] {
                cache.begin(s1 < end ? planner.query_from(s1) : kInf);
                field = std::make_unique<MpuField>(in.points, field_params, &fst, FieldProgress{}, nullptr, &region, &cache);
            });
            rep.coverage_seconds += in.coverage_seconds;
            if (in.points.size() > 0)
                field_per_point = std::max(field_per_point, static_cast<double>(fst.memory_bytes) / static_cast<double>(in.points.size()));
            if (!field->region_exact()) {  // load the bricks the lacking balls meet, and build again
                if (add_lacking_bricks(*field, index, extra, seen) == 0) halo *= 2;  // (cannot happen: a lacking ball meets an unloaded brick)
                ++rep.retries;
                continue;
            }
            if (field->over_budget()) {  // fewer layers (as many as the field's size allows), or no kept fits
                ++rep.retries;
                const double need = static_cast<double>(fst.memory_bytes);
                if (fewer_layers_or_no_kept_fits(s0, s1, cache, static_cast<double>(region.max_field_bytes) / need)) continue;
                throw budget_too_small(store, planner, s0, halo0, in.points.size(), need, others, fixed, sp);
            }
            BatchBuffer buf(Payload::points);
            ScatteredIsosurfaceStats part;
            if (in.coverage) in.coverage->set_part_of(region.loaded);
            StencilSource source{StencilGrid(g.dims), s0 * planner.stencils_per_layer(), s1 * planner.stencils_per_layer()};
            const StencilSeedStage seed(in.stencils(*field), iso, n);
            static_cast<SeedProjection&>(part) = run_seed_projection(source, seed, *field, iso, np, nullptr, buf, opt, {});
            part.seeds = seed.stats();
            if (in.coverage && !in.coverage->part_exact()) {  // the support test reached past the loaded z range
                halo *= 2;
                ++rep.retries;
                continue;
            }
            cache.advance();
            buf.forward(sink, seq);
            record_slab(st, rep, part, fst, halo / g.cell.z);
            if (progress) progress(static_cast<double>((s1 - s0) * planner.stencils_per_layer()));
            break;
        }
        s0 = s1;
    }
    rep.reused_fits = cache.hits();
    st.projected = true;
    sink.finish();
    if (dedup_sink) st.dedup_removed = dedup_sink->removed();
    if (report) *report = rep;
    return st;
}

BinningSummary binning_summary(const ScatteredStorePlan& plan) {
    return BinningSummary{plan.grid, plan.frame.points, plan.dropped_nonfinite, plan.empty_cells, plan.empty_interior_cells,
                          plan.max_per_cell};
}

void print_store_isosurface_stats(std::FILE* out, const char* cmd, const ScatteredStorePlan& plan, const ScatteredStoreReport& rep,
                                  const ScatteredIsosurfaceStats& st, int n, const FieldProjectParams& np, double dedup,
                                  std::size_t points, const IsosurfaceRunTimes& t, int threads) {
    print_scattered_stats(out, cmd, binning_summary(plan), st.seeds, n);
    print_newton_stats(out, cmd, "mpu", np, st.newton, st.newton_busy_seconds);
    if (dedup > 0) print_dedup_stats(out, cmd, dedup, st.dedup_removed);
    std::fprintf(out,
                 "%s: point store in %d slabs (%d built again over more points; halo up to %.1f cells), at most %llu of %llu points "
                 "loaded at once (%llu loaded in all), %llu locals (%llu fits copied from the slab before, %llu regularised), largest slab field %.1f MiB\n",
                 cmd, rep.slabs, rep.retries, rep.halo_cells, static_cast<unsigned long long>(rep.most_loaded),
                 static_cast<unsigned long long>(plan.frame.points), static_cast<unsigned long long>(rep.loaded),
                 static_cast<unsigned long long>(rep.field.locals), static_cast<unsigned long long>(rep.reused_fits),
                 static_cast<unsigned long long>(rep.field.regularised),
                 static_cast<double>(rep.field.memory_bytes) / 1048576.0);
    std::fprintf(out,
                 "%s: %zu points; time: plan (%d scans of the store) %.3f s, read %.3f s, coverage %.3f s and field %.3f s side by side, "
                 "isosurface %.3f s (busy: stencils %.3f s, Newton %.3f s over %d thread(s)), total %.3f s\n",
                 cmd, points, plan.scans, plan.seconds, rep.read_seconds, rep.coverage_seconds, rep.field_seconds, t.graph,
                 st.seed_busy_seconds, st.newton_busy_seconds, threads, t.total);
}

}  // namespace meshless
