#include "kernels/point_set.hpp"
#include "kernels/rbf_grid_field.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <string>

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "kernels/errors.hpp"
#include "kernels/field_input.hpp"
#include "kernels/flat_hull.hpp"
#include "kernels/local_multiquadric_fit.hpp"
#include "kernels/batch_order.hpp"
#include "kernels/partition_of_unity.hpp"

namespace meshless {

namespace {
/// Rings of cells a flat local searches for points off its plane (kernels/flat_hull.hpp): the
/// blunt fin's x-planes lie up to 6.4 cells apart.
constexpr std::int64_t kSpanRings = 8;
}  // namespace

RbfGridField::RbfGridField(const PointSet& points, const FieldParams& params, FieldBuildStats* stats,
                           const FieldProgress& progress) {
    if (!(params.binning_m > 0) || !std::isfinite(params.binning_m))
        throw InvalidArgument("rbf-grid: binning constant m must be > 0");
    if (params.rbf_grid_max_local < 8) throw InvalidArgument("rbf-grid: rbf_grid_max_local must be >= 8");
    if (params.rbf_grid_min_local < 1 || params.rbf_grid_min_local > params.rbf_grid_max_local)
        throw InvalidArgument("rbf-grid: rbf_grid_min_local must be in 1..rbf_grid_max_local");
    FieldBuildStats local_stats;
    FieldBuildStats& st = stats ? *stats : local_stats;
    MergedPoints mp = prepare_field_points(points, params, "rbf-grid", &st);
    origin_ = mp.origin;
    scale_ = mp.scale;
    bounds_ = points.bounds();
    {
        const auto [plo, phi] = bounding_box(mp.pos);
        morton_order_points(mp, plo, phi);  // cache-friendly neighbourhoods and fits
    }
    const std::vector<Vec3> pts = std::move(mp.pos);
    const std::vector<double>& val = mp.value;
    const double c = hardy_c_world_for(params, bounds_);
    const std::size_t n = pts.size();

    // ---- RBF grid dimensions (section 4.3), degenerate axes folded out.
    const auto [lo, hi] = bounding_box(pts);
    lo_ = lo;
    const double w[3] = {hi.x - lo.x, hi.y - lo.y, hi.z - lo.z};
    const double wmax = std::max({w[0], w[1], w[2]});
    bool active[3];
    for (int a = 0; a < 3; ++a) active[a] = w[a] > 1e-9 * wmax;
    double s = 0;
    for (;;) {
        int k = 0;
        double prod = 1;
        for (int a = 0; a < 3; ++a)
            if (active[a]) { prod *= w[a]; ++k; }
        if (k == 0) break;
        s = std::pow(params.binning_m * prod / static_cast<double>(n), 1.0 / k);
        bool changed = false;
        for (int a = 0; a < 3; ++a)
            if (active[a] && w[a] / s < 0.5) { active[a] = false; changed = true; }
        if (!changed) break;
    }
    // the binning constant sets the cell count (about n / m): one too small for the points asks for
    // more cells than the field may hold, a parameter's fault that names the option
    const auto too_large = [&](double cells) {
        char m[32];
        std::snprintf(m, sizeof m, "%g", params.binning_m);
        char c[32];
        std::snprintf(c, sizeof c, "%.4g", cells);
        return InvalidArgument(std::string("--binning ") + m + ": rbf-grid: an internal grid of " + c + " cells for " +
                               std::to_string(n) + " points is too large (at most 8 cells a point; a larger --binning gives fewer)");
    };
    double sc[3];
    double cells_wanted = 1;
    for (int a = 0; a < 3; ++a) cells_wanted *= active[a] ? std::max(1.0, std::round(w[a] / s)) : 1.0;
    if (!(cells_wanted <= static_cast<double>(8 * n + 64)) || !(cells_wanted <= 0x7FFFFFFF)) throw too_large(cells_wanted);
    for (int a = 0; a < 3; ++a) {
        n_[a] = active[a] ? std::max<std::int64_t>(1, std::llround(w[a] / s)) : 1;
        sc[a] = w[a] / static_cast<double>(n_[a]);
    }
    s_ = {sc[0], sc[1], sc[2]};
    inv_s_ = {n_[0] > 1 ? 1 / sc[0] : 0.0, n_[1] > 1 ? 1 / sc[1] : 0.0, n_[2] > 1 ? 1 / sc[2] : 0.0};
    const std::int64_t ncells = n_[0] * n_[1] * n_[2];
    if (ncells > static_cast<std::int64_t>(8 * n + 64) || ncells > 0x7FFFFFFF)
        throw too_large(static_cast<double>(ncells));
    st.grid_dims = {n_[0], n_[1], n_[2]};

    const double diag = norm(s_);
    r_data_ = 2 * diag;
    if (params.rbf_grid_support == RbfGridSupport::paper_radius) {
        r_w_ = r_data_;
    } else {
        double m = std::numeric_limits<double>::infinity();
        for (int a = 0; a < 3; ++a)
            if (n_[a] >= 3) m = std::min(m, 1.5 * sc[a]);
        r_w_ = std::isfinite(m) ? m : r_data_;
        r_w_ = std::min(std::max(r_w_, 1.01 * 0.5 * diag), r_data_);
    }
    if (!(r_w_ > 0)) r_w_ = r_data_ = 1;  // a single point (after merging): one constant local
    for (int a = 0; a < 3; ++a) reach_[a] = n_[a] < 2 ? 0.0 : r_w_ / sc[a];

    // ---- Bin the points (counting sort by cell; within a cell in the Morton order given above).
    auto cell_of = [&](const Vec3& p, std::int64_t ci[3]) {
        for (int a = 0; a < 3; ++a) {
            const double u = (p[a] - lo_[a]) * inv_s_[a];
            ci[a] = std::clamp<std::int64_t>(static_cast<std::int64_t>(std::floor(u)), 0, n_[a] - 1);
        }
    };
    std::vector<std::uint32_t> start(static_cast<std::size_t>(ncells) + 1, 0), order(n);
    std::vector<std::uint32_t> pcell(n);
    for (std::size_t i = 0; i < n; ++i) {
        std::int64_t ci[3];
        cell_of(pts[i], ci);
        pcell[i] = static_cast<std::uint32_t>(ci[0] + n_[0] * (ci[1] + n_[1] * ci[2]));
        ++start[pcell[i] + 1];
    }
    for (std::int64_t k = 0; k < ncells; ++k) start[k + 1] += start[k];
    {
        std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
        for (std::size_t i = 0; i < n; ++i) order[fill[pcell[i]]++] = static_cast<std::uint32_t>(i);
    }
    std::vector<std::uint32_t>().swap(pcell);

    auto centre_of = [&](std::int64_t i, std::int64_t j, std::int64_t k) {
        return Vec3{lo_.x + (i + 0.5) * sc[0], lo_.y + (j + 0.5) * sc[1], lo_.z + (k + 0.5) * sc[2]};
    };
    const double rd2 = r_data_ * r_data_ * (1 + 1e-12);
    // Visit the points of the 27 neighbouring cells inside the data sphere of cell `cell`.
    auto gather = [&](std::int64_t cell, auto&& fn) {
        const std::int64_t i = cell % n_[0], j = (cell / n_[0]) % n_[1], k = cell / (n_[0] * n_[1]);
        const Vec3 cc = centre_of(i, j, k);
        for (std::int64_t z = std::max<std::int64_t>(0, k - 1); z <= std::min(n_[2] - 1, k + 1); ++z)
            for (std::int64_t y = std::max<std::int64_t>(0, j - 1); y <= std::min(n_[1] - 1, j + 1); ++y)
                for (std::int64_t x = std::max<std::int64_t>(0, i - 1); x <= std::min(n_[0] - 1, i + 1); ++x) {
                    const std::int64_t nc = x + n_[0] * (y + n_[1] * z);
                    for (std::uint32_t q = start[nc]; q < start[nc + 1]; ++q) {
                        const std::uint32_t pi = order[q];
                        const Vec3 e = pts[pi] - cc;
                        if (dot(e, e) <= rd2) fn(pi, e);
                    }
                }
    };

    // Sparse local: the `want` points nearest to the centre, from cubes of cells growing by rings.
    auto grow = [&](std::int64_t cell, std::uint32_t want, std::vector<std::pair<double, std::uint32_t>>& near,
                    std::vector<std::uint32_t>& out) {
        const std::int64_t i = cell % n_[0], j = (cell / n_[0]) % n_[1], k = cell / (n_[0] * n_[1]);
        const Vec3 cc = centre_of(i, j, k);
        const std::int64_t rmax = std::max({n_[0], n_[1], n_[2]});
        for (std::int64_t r = 2;; ++r) {
            near.clear();
            for (std::int64_t z = std::max<std::int64_t>(0, k - r); z <= std::min(n_[2] - 1, k + r); ++z)
                for (std::int64_t y = std::max<std::int64_t>(0, j - r); y <= std::min(n_[1] - 1, j + r); ++y)
                    for (std::int64_t x = std::max<std::int64_t>(0, i - r); x <= std::min(n_[0] - 1, i + r); ++x) {
                        const std::int64_t nc = x + n_[0] * (y + n_[1] * z);
                        for (std::uint32_t q = start[nc]; q < start[nc + 1]; ++q) {
                            const Vec3 e = pts[order[q]] - cc;
                            near.emplace_back(dot(e, e), order[q]);
                        }
                    }
            if (near.size() >= want || r >= rmax) break;
        }
        const std::size_t take = std::min<std::size_t>(want, near.size());
        std::partial_sort(near.begin(), near.begin() + static_cast<std::ptrdiff_t>(take), near.end());
        out.clear();
        for (std::size_t q = 0; q < take; ++q) out.push_back(near[q].second);
        std::sort(out.begin(), out.end());
    };

    // ---- Count the points of every local, then lay out the arrays.
    const std::uint32_t cap = params.rbf_grid_max_local, min_local = std::min<std::uint32_t>(params.rbf_grid_min_local, static_cast<std::uint32_t>(n));
    // A flat local (coplanar or collinear points: a grid whose planes lie farther apart than the
    // bins, such as the blunt fin's x-planes, 1.5-3.5 units apart with bins of 0.55) keeps its
    // points and takes the `extra` nearest points off their hull from growing rings of cells, so
    // that its linear part is determined across the plane instead of guessed by regularisation.
    // base: the local's points (its nearest `keep`); out: base + those, sorted; at most `cap`.
    auto span_hull = [&](std::int64_t cell, const FlatHull& h, std::vector<std::uint32_t> base, std::uint32_t extra,
                         std::vector<std::pair<double, std::uint32_t>>& near, std::vector<std::uint32_t>& out) {
        const std::int64_t i = cell % n_[0], j = (cell / n_[0]) % n_[1], k = cell / (n_[0] * n_[1]);
        const Vec3 cc = centre_of(i, j, k);
        // rings of cells, each scanned once (its shell), until `extra` points off the hull are
        // found, at most kSpanRings rings out: a bounded search, whatever lies beyond
        const std::int64_t rmax = std::min<std::int64_t>(kSpanRings, std::max({n_[0], n_[1], n_[2]}));
        near.clear();
        for (std::int64_t r = 1; r <= rmax && near.size() < extra; ++r)
            for (std::int64_t z = std::max<std::int64_t>(0, k - r); z <= std::min(n_[2] - 1, k + r); ++z)
                for (std::int64_t y = std::max<std::int64_t>(0, j - r); y <= std::min(n_[1] - 1, j + r); ++y)
                    for (std::int64_t x = std::max<std::int64_t>(0, i - r); x <= std::min(n_[0] - 1, i + r); ++x) {
                        if (std::max({std::abs(x - i), std::abs(y - j), std::abs(z - k)}) != r) continue;  // inner: seen
                        const std::int64_t nc = x + n_[0] * (y + n_[1] * z);
                        for (std::uint32_t q = start[nc]; q < start[nc + 1]; ++q) {
                            const Vec3& p = pts[order[q]];
                            if (h.off(p)) near.emplace_back(dot(p - cc, p - cc), order[q]);
                        }
                    }
        const std::size_t take = std::min<std::size_t>(extra, near.size());
        std::partial_sort(near.begin(), near.begin() + static_cast<std::ptrdiff_t>(take), near.end());
        if (base.size() + take > cap) base.resize(cap - take);  // (base is nearest first)
        out = std::move(base);
        for (std::size_t q = 0; q < take; ++q) out.push_back(near[q].second);
        std::sort(out.begin(), out.end());
        out.erase(std::unique(out.begin(), out.end()), out.end());  // (a base point may also count as off)
        return take;
    };

    // Flat data (all of it in one plane or line: 2-D scattered data) has no point off any local's
    // plane: the search is skipped (it would scan every ring of every local for nothing).
    const bool data_flat = all_flat(pts);
    // count: points in the data sphere (or grown); keep: how many the local uses, the nearest
    // max(K, points within R_w) of them (K = rbf_grid_local_points, 0 = all), at most `cap`.
    const std::uint32_t k_near = params.rbf_grid_local_points;
    const double rw2 = r_w_ * r_w_ * (1 + 1e-12);
    std::vector<std::uint32_t> count(static_cast<std::size_t>(ncells), 0), keep(static_cast<std::size_t>(ncells), 0);
    std::vector<std::vector<std::uint32_t>> grown(static_cast<std::size_t>(ncells));
    std::vector<std::uint8_t> spanned(static_cast<std::size_t>(ncells), 0);  // flat locals given points off their plane
    tbb::enumerable_thread_specific<std::vector<std::pair<double, std::uint32_t>>> scratch;
    tbb::parallel_for(tbb::blocked_range<std::int64_t>(0, ncells, 256), [&](const tbb::blocked_range<std::int64_t>& r) {
        auto& near = scratch.local();
        for (std::int64_t cell = r.begin(); cell != r.end(); ++cell) {
            std::uint32_t cnt = 0, in_w = 0;
            PointMoments mo;
            mo.ref = centre_of(cell % n_[0], (cell / n_[0]) % n_[1], cell / (n_[0] * n_[1]));
            gather(cell, [&](std::uint32_t, const Vec3& e) { ++cnt; in_w += dot(e, e) <= rw2; mo.add(e); });
            if (cnt > 0 && cnt < min_local) {
                grow(cell, min_local, near, grown[cell]);
                cnt = static_cast<std::uint32_t>(grown[cell].size());
                in_w = cnt;
                mo = PointMoments{mo.ref};
                for (std::uint32_t pi : grown[cell]) mo.add(pts[pi] - mo.ref);
            }
            std::uint32_t want = k_near == 0 ? cnt : std::max(k_near, in_w);
            const std::optional<FlatHull> hull = cnt > 0 && !data_flat ? flat_hull(mo) : std::nullopt;
            if (hull) {
                // the local's own points, nearest first, then the nearest off their hull
                std::vector<std::uint32_t> base;
                const std::uint32_t used = std::min({cnt, want, cap});
                near.clear();
                if (!grown[cell].empty()) {
                    for (std::uint32_t pi : grown[cell]) near.emplace_back(dot(pts[pi] - mo.ref, pts[pi] - mo.ref), pi);
                } else {
                    gather(cell, [&](std::uint32_t pi, const Vec3& e) { near.emplace_back(dot(e, e), pi); });
                }
                std::sort(near.begin(), near.end());
                for (std::uint32_t q = 0; q < used; ++q) base.push_back(near[q].second);
                std::vector<std::uint32_t> spanned_list;
                spanned[cell] = span_hull(cell, *hull, std::move(base), std::max<std::uint32_t>(4, min_local / 2), near, spanned_list) > 0;
                if (spanned[cell]) {  // (nothing found: the local stays as it was, not an explicit copy)
                    grown[cell] = std::move(spanned_list);
                    cnt = static_cast<std::uint32_t>(grown[cell].size());
                    want = cnt;
                }
            }
            count[cell] = cnt;
            keep[cell] = std::min({cnt, want, cap});
        }
    });
    // A local over its whole 27-cell block (the data sphere always contains the block: its corner
    // is 1.5 |s| < R from the centre) reads the points as up to 9 runs of the cell-sorted arrays,
    // one per (y, z) row of the block, in exactly the order gather() visits them. A grown or capped
    // local gets copies of its points after the sorted ones, one run.
    cell_local_.assign(static_cast<std::size_t>(ncells), -1);
    std::vector<std::int64_t> local_cell;
    std::vector<std::uint8_t> explicit_pts;
    std::uint64_t total = 0, extra = 0;
    run_first_.push_back(0);
    for (std::int64_t cell = 0; cell < ncells; ++cell) {
        if (count[cell] == 0) continue;
        cell_local_[cell] = static_cast<std::int32_t>(local_cell.size());
        local_cell.push_back(cell);
        MultiquadricLocal h;
        h.first = static_cast<std::uint32_t>(total);
        locals_.push_back(h);
        const std::uint32_t used = keep[cell];
        total += used;
        if (total > 0xFFFFFFF0ull || n + extra + used > 0xFFFFFFF0ull)
            throw InvalidArgument("rbf-grid: too many local points (" + std::to_string(total) + ")");
        const bool expl = !grown[cell].empty() || used < count[cell];
        explicit_pts.push_back(expl);
        if (expl) {
            runs_.push_back(MqRun{static_cast<std::uint32_t>(n + extra), used});
            extra += used;
        } else {
            const std::int64_t i = cell % n_[0], j = (cell / n_[0]) % n_[1], k = cell / (n_[0] * n_[1]);
            const std::int64_t x0 = std::max<std::int64_t>(0, i - 1), x1 = std::min(n_[0] - 1, i + 1);
            for (std::int64_t z = std::max<std::int64_t>(0, k - 1); z <= std::min(n_[2] - 1, k + 1); ++z)
                for (std::int64_t y = std::max<std::int64_t>(0, j - 1); y <= std::min(n_[1] - 1, j + 1); ++y) {
                    const std::int64_t row = n_[0] * (y + n_[1] * z);
                    const std::uint32_t b = start[row + x0], e = start[row + x1 + 1];
                    if (e > b) runs_.push_back(MqRun{b, e - b});
                }
        }
        run_first_.push_back(static_cast<std::uint32_t>(runs_.size()));
    }
    lambda_.assign(total, 0.0);
    px_.resize(n + extra);
    py_.resize(n + extra);
    pz_.resize(n + extra);
    for (std::size_t q = 0; q < n; ++q) {
        const Vec3& p = pts[order[q]];
        px_[q] = p.x;
        py_[q] = p.y;
        pz_[q] = p.z;
    }

    // ---- Fit every local (parallel, independent: the result does not depend on the thread count).
    std::vector<MultiquadricOutcome> outcome(locals_.size());
    std::vector<std::uint8_t> rank_def(locals_.size(), 0), capped(locals_.size(), 0), refit(locals_.size(), 0);
    tbb::enumerable_thread_specific<MultiquadricSolver> solvers;
    tbb::enumerable_thread_specific<std::vector<std::uint32_t>> idx_scratch;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, locals_.size(), 16), [&](const tbb::blocked_range<std::size_t>& r) {
        MultiquadricSolver& solver = solvers.local();
        auto& near = scratch.local();
        auto& idxv = idx_scratch.local();
        for (std::size_t l = r.begin(); l != r.end(); ++l) {
            const std::int64_t cell = local_cell[l];
            MultiquadricLocal& h = locals_[l];
            const std::uint32_t cnt = count[cell];
            const std::uint32_t used = keep[cell];
            idxv.resize(used);
            std::uint32_t* out = idxv.data();
            if (!grown[cell].empty()) {
                std::copy(grown[cell].begin(), grown[cell].end(), out);
            } else if (used == cnt) {
                std::uint32_t k = 0;
                gather(cell, [&](std::uint32_t pi, const Vec3&) { out[k++] = pi; });
            } else {  // keep the `used` nearest points (ties by index), in index order
                near.clear();
                gather(cell, [&](std::uint32_t pi, const Vec3& e) { near.emplace_back(dot(e, e), pi); });
                std::nth_element(near.begin(), near.begin() + used, near.end());
                for (std::uint32_t k = 0; k < used; ++k) out[k] = near[k].second;
                std::sort(out, out + used);
                // capped: the size cap, not K, dropped points inside the weight radius
                capped[l] = used == cap && near[used].first <= rw2;
            }
            const std::span<const std::uint32_t> mine(out, used);
            const LocalFitResult res = fit_local_multiquadric(solver, pts, val, mine, c, params, h, std::span<double>(lambda_.data() + h.first, used));
            outcome[l] = res.fit.outcome;
            rank_def[l] = res.fit.poly_rank < 4;
            refit[l] = res.refitted;
            if (explicit_pts[l]) {
                const std::uint32_t at = runs_[run_first_[l]].start;
                for (std::uint32_t k = 0; k < used; ++k) {
                    const Vec3& p = pts[out[k]];
                    px_[at + k] = p.x;
                    py_[at + k] = p.y;
                    pz_[at + k] = p.z;
                }
            }
        }
        if (progress) progress(static_cast<double>(r.size()), static_cast<double>(locals_.size()));
    });



    st.locals = locals_.size();
    std::uint64_t sum_pts = 0;
    for (std::size_t l = 0; l < locals_.size(); ++l) {
        st.interpolated += outcome[l] == MultiquadricOutcome::interpolated;
        st.regularised += outcome[l] == MultiquadricOutcome::regularised;
        st.linear_fallback += outcome[l] == MultiquadricOutcome::linear_fallback;
        st.polynomial_only += outcome[l] == MultiquadricOutcome::polynomial_only;
        st.rank_deficient += rank_def[l];
        st.refitted += refit[l];
        st.c_lowered += locals_[l].c2 < c * c;
        st.mean_local_c += std::sqrt(locals_[l].c2);
        st.capped += capped[l];
        st.grown += !grown[local_cell[l]].empty();
        st.spanned += spanned[local_cell[l]];
        const std::uint64_t used = (l + 1 < locals_.size() ? locals_[l + 1].first : total) - locals_[l].first;
        sum_pts += used;
        st.max_local_points = std::max<std::uint64_t>(st.max_local_points, used);
    }
    st.mean_local_points = locals_.empty() ? 0.0 : static_cast<double>(sum_pts) / static_cast<double>(locals_.size());
    st.mean_local_c = locals_.empty() ? 0.0 : st.mean_local_c / static_cast<double>(locals_.size());
    st.memory_bytes = px_.size() * 3 * sizeof(double) + cell_local_.size() * sizeof(std::int32_t) +
                      locals_.size() * sizeof(MultiquadricLocal) + run_first_.size() * sizeof(std::uint32_t) +
                      runs_.size() * sizeof(MqRun) + total * sizeof(double);
}

std::uint32_t RbfGridField::batch_key(const Vec3& pw) const {
    const Vec3 dw = pw - origin_;
    const Vec3 x{dw.x * scale_.x, dw.y * scale_.y, dw.z * scale_.z};
    std::uint32_t ci[3];
    const int shift = morton_shift(std::max({n_[0], n_[1], n_[2]}));
    for (int a = 0; a < 3; ++a) {
        const double u = (x[a] - lo_[a]) * inv_s_[a];
        if (!(u == u)) return 0xFFFFFFFFu;
        ci[a] = static_cast<std::uint32_t>(std::clamp(std::floor(u), 0.0, static_cast<double>(n_[a] - 1))) >> shift;
    }
    return morton_key(ci[0], ci[1], ci[2]);
}

void RbfGridField::evaluate(std::span<const Vec3> p, std::span<double> value, std::span<Vec3> grad) const {
    PuBlend blend;
    EvalScratch sc;
    const bool want_grad = !grad.empty();
    for_each_in_key_order(p.size(), [&](std::size_t t) { return batch_key(p[t]); },
                          [&](std::size_t t) { eval_one(p[t], value[t], want_grad ? &grad[t] : nullptr, blend, sc); },
                          [&](std::size_t t) {
                              __builtin_prefetch(&p[t]);
                              __builtin_prefetch(&value[t], 1);
                              if (want_grad) __builtin_prefetch(&grad[t], 1);
                          });
}

void RbfGridField::eval_one(const Vec3& pw, double& value, Vec3* grad, PuBlend& blend, EvalScratch& sc) const {
    const bool want_grad = grad != nullptr;
    const double nan = std::numeric_limits<double>::quiet_NaN();
    {
        const Vec3 dw = pw - origin_;
        const Vec3 x{dw.x * scale_.x, dw.y * scale_.y, dw.z * scale_.z};
        if (!std::isfinite(x.x) || !std::isfinite(x.y) || !std::isfinite(x.z)) {
            value = nan;
            if (want_grad) *grad = {nan, nan, nan};
            return;
        }        // Centres within R_w of x on every axis: |u - i| < R_w / s_a, u = cell coordinate - 1/2
        // (a little wider; the sphere test below decides).
        std::int64_t c0[3], c1[3];
        for (int a = 0; a < 3; ++a) {
            if (n_[a] < 2) {
                c0[a] = c1[a] = 0;
                continue;
            }
            const double u = (x[a] - lo_[a]) * inv_s_[a] - 0.5;
            const double top = static_cast<double>(n_[a] - 1);
            c0[a] = static_cast<std::int64_t>(std::clamp(std::ceil(u - reach_[a] - 1e-6), 0.0, top + 1));
            c1[a] = static_cast<std::int64_t>(std::clamp(std::floor(u + reach_[a] + 1e-6), -1.0, top));
        }
        blend.reset();
        // branch-free selection of the locals whose weight sphere holds x
        const std::size_t span = static_cast<std::size_t>(std::max<std::int64_t>(0, c1[0] - c0[0] + 1) *
                                                          std::max<std::int64_t>(0, c1[1] - c0[1] + 1) *
                                                          std::max<std::int64_t>(0, c1[2] - c0[2] + 1));
        sc.local.resize(span);
        sc.centre.resize(span);
        sc.dist.resize(span);
        std::size_t m = 0;
        const double rw2 = r_w_ * r_w_;
        for (std::int64_t k = c0[2]; k <= c1[2]; ++k)
            for (std::int64_t j = c0[1]; j <= c1[1]; ++j) {
                const std::int32_t* row = cell_local_.data() + n_[0] * (j + n_[1] * k);
                for (std::int64_t i = c0[0]; i <= c1[0]; ++i) {
                    const std::int32_t l = row[i];
                    const Vec3 cc{lo_.x + (i + 0.5) * s_.x, lo_.y + (j + 0.5) * s_.y, lo_.z + (k + 0.5) * s_.z};
                    const Vec3 e = x - cc;
                    const double d2 = dot(e, e);
                    sc.local[m] = l;
                    sc.centre[m] = cc;
                    sc.dist[m] = d2;
                    m += l >= 0 && d2 < rw2;
                }
            }
        sc.local.resize(m);
        sc.terms.resize(m);
        for (std::size_t t = 0; t < m; ++t) {
            const std::int32_t l = sc.local[t];
            const MultiquadricLocal& h = locals_[static_cast<std::size_t>(l)];
            const std::uint32_t r0 = run_first_[l], nr = h.count > 0 ? run_first_[l + 1] - r0 : 0;
            sc.terms[t] = MqLocalTerms{runs_.data() + r0, nr, lambda_.data() + h.first, h.c2};
            sc.dist[t] = std::sqrt(sc.dist[t]);
            __builtin_prefetch(lambda_.data() + h.first);  // the misses of all the locals overlap
        }
        const std::size_t nl = sc.local.size();
        sc.sums.resize(nl);
        multiquadric_sums(px_.data(), py_.data(), pz_.data(), sc.terms, x, want_grad, sc.sums.data());
        for (std::size_t t = 0; t < nl; ++t) {
            const MultiquadricLocal& h = locals_[static_cast<std::size_t>(sc.local[t])];
            const MqSum& acc = sc.sums[t];
            const double q = h.a0 + dot(h.a, x - h.origin) + acc.v;
            blend.add(x, sc.centre[t], r_w_, sc.dist[t], q, want_grad ? h.a + Vec3{acc.gx, acc.gy, acc.gz} : h.a);
        }
        value = blend.finish(grad);
        if (want_grad) *grad = {grad->x * scale_.x, grad->y * scale_.y, grad->z * scale_.z};
    }
}

}  // namespace meshless

namespace meshless {

void RbfGridField::save_state(FieldStateWriter& w) const {
    put_frame(w, origin_, scale_, bounds_);
    const double grid[14] = {lo_.x,    lo_.y,    lo_.z,      s_.x,       s_.y,       s_.z,    inv_s_.x,
                             inv_s_.y, inv_s_.z, reach_[0], reach_[1], reach_[2], r_data_, r_w_};
    w.put("grid", std::span<const double>(grid, 14));
    const std::int64_t dims[3] = {n_[0], n_[1], n_[2]};
    w.put("dims", std::span<const std::int64_t>(dims, 3));
    w.put("px", std::span<const double>(px_));
    w.put("py", std::span<const double>(py_));
    w.put("pz", std::span<const double>(pz_));
    w.put("cell_local", std::span<const std::int32_t>(cell_local_));
    put_locals(w, locals_);
    w.put("run_first", std::span<const std::uint32_t>(run_first_));
    std::vector<std::uint32_t> runs;
    runs.reserve(2 * runs_.size());
    for (const MqRun& r : runs_) runs.insert(runs.end(), {r.start, r.count});
    w.put("runs", std::span<const std::uint32_t>(runs));
    w.put("lambda", std::span<const double>(lambda_));
}

namespace {
constexpr double kMaxVisitedCells = 4096;  // cells a query may visit; a built grid: <= 3375 (load_state)
}  // namespace

std::unique_ptr<RbfGridField> RbfGridField::load_state(FieldState& s) {
    std::unique_ptr<RbfGridField> f(new RbfGridField);
    take_frame(s, f->origin_, f->scale_, f->bounds_);
    {
        const std::vector<std::int64_t> d = s.take_i64("dims", 3);
        std::int64_t cells = 1;
        for (int a = 0; a < 3; ++a) {
            if (d[a] < 1 || d[a] > 0x7FFFFFFF) s.fail("dims", "grid dimension " + std::to_string(d[a]) + " outside 1..2^31-1");
            f->n_[a] = d[a];
            if (cells > 0x7FFFFFFF / d[a]) s.fail("dims", "grid of more than 2^31-1 cells");
            cells *= d[a];
        }
    }
    const std::vector<double> g = s.take_f64("grid", 14);
    for (double v : g)
        if (!std::isfinite(v)) s.fail("grid", "non-finite grid value");
    f->lo_ = {g[0], g[1], g[2]};
    f->s_ = {g[3], g[4], g[5]};
    f->inv_s_ = {g[6], g[7], g[8]};
    f->r_data_ = g[12];
    f->r_w_ = g[13];
    for (int a = 0; a < 3; ++a) {
        f->reach_[a] = g[9 + a];
        const double sa = f->s_[a];
        if (!(sa >= 0) || (f->n_[a] > 1 && !(sa > 0))) s.fail("grid", "cell edge not > 0");
        const double inv = f->n_[a] > 1 ? 1 / sa : 0.0;
        if (std::bit_cast<std::uint64_t>(inv) != std::bit_cast<std::uint64_t>(f->inv_s_[a]))
            s.fail("grid", "1/cell edge does not match the cell edge");
    }
    const double diag = norm(f->s_);  // as built: r_data = 2 |s|, 0 < r_w <= r_data; all points merged into one: 1, 1
    if (diag > 0) {
        if (std::bit_cast<std::uint64_t>(f->r_data_) != std::bit_cast<std::uint64_t>(2 * diag))
            s.fail("grid", "data radius is not 2 |s|");
        if (!(f->r_w_ > 0 && f->r_w_ <= f->r_data_)) s.fail("grid", "weight radius outside (0, data radius]");
    } else if (f->r_data_ != 1.0 || f->r_w_ != 1.0) {
        s.fail("grid", "radii of a single-point grid are not 1");
    }
    for (int a = 0; a < 3; ++a) {
        const double reach = f->n_[a] < 2 ? 0.0 : f->r_w_ / f->s_[a];
        if (std::bit_cast<std::uint64_t>(reach) != std::bit_cast<std::uint64_t>(f->reach_[a]))
            s.fail("grid", "reach does not match the weight radius");
    }
    // A query visits the cells within the reach along every axis (at most floor(2 reach) + 2 of an
    // axis's cells), so the reach bounds the work of one evaluation. A built grid has near-cubic
    // cells: every edge is below 1.5 s (s = the binning edge) and an edge of an axis with >= 2 cells
    // is at least 0.75 s, so reach = r_w / s_a <= 2 |s_| / (0.75 s) < 2 sqrt(3) 1.5 / 0.75 = 6.93,
    // counted here as at most 15 cells per axis, 3375 per query. A forged grid with a tiny edge
    // along an axis of many cells would make every query scan that whole axis.
    {
        double visited = 1;
        for (int a = 0; a < 3; ++a)
            visited *= std::min(static_cast<double>(f->n_[a]), std::floor(2 * f->reach_[a]) + 2);
        if (visited > kMaxVisitedCells)
            s.fail("grid", "weight radius spans " + std::to_string(static_cast<std::uint64_t>(visited)) +
                               " cells per query (a built grid spans at most 3375)");
    }
    const std::size_t ncells = static_cast<std::size_t>(f->n_[0] * f->n_[1] * f->n_[2]);

    f->px_ = s.take_f64("px");
    const std::size_t np = f->px_.size();
    f->py_ = s.take_f64("py", np);
    f->pz_ = s.take_f64("pz", np);
    if (np == 0 || np > 0xFFFFFFF0u) s.fail("px", "point count " + std::to_string(np) + " outside 1..2^32-16");
    if (f->py_.size() != np || f->pz_.size() != np) s.fail("py", "px, py, pz differ in length");
    f->locals_ = take_locals(s);
    const std::size_t nl = f->locals_.size();
    if (nl == 0) s.fail("locals", "no local interpolant");
    f->cell_local_ = s.take_i32("cell_local", ncells);
    if (f->cell_local_.size() != ncells) s.fail("cell_local", "not one entry per grid cell");
    for (std::size_t c = 0; c < ncells; ++c) {
        const std::int32_t l = f->cell_local_[c];
        if (l < -1 || (l >= 0 && static_cast<std::size_t>(l) >= nl))
            s.fail("cell_local", "cell " + std::to_string(c) + " names local " + std::to_string(l) + " of " + std::to_string(nl));
    }
    f->run_first_ = s.take_u32("run_first", nl + 1);
    {
        const std::vector<std::uint32_t> runs = s.take_u32("runs");
        if (runs.size() % 2 != 0) s.fail("runs", "odd number of run values");
        f->runs_.resize(runs.size() / 2);
        for (std::size_t r = 0; r < f->runs_.size(); ++r) {
            f->runs_[r] = MqRun{runs[2 * r], runs[2 * r + 1]};
            if (static_cast<std::uint64_t>(runs[2 * r]) + runs[2 * r + 1] > np)
                s.fail("runs", "run " + std::to_string(r) + " ends at point " +
                                   std::to_string(static_cast<std::uint64_t>(runs[2 * r]) + runs[2 * r + 1]) +
                                   ", beyond the " + std::to_string(np) + " points");
        }
    }
    if (f->run_first_[0] != 0 || f->run_first_[nl] != f->runs_.size())
        s.fail("run_first", "run table does not span the runs");
    for (std::size_t l = 0; l < nl; ++l)  // with the ends checked above, every entry is <= the run count
        if (f->run_first_[l] > f->run_first_[l + 1]) s.fail("run_first", "run table not ascending at local " + std::to_string(l));
    f->lambda_ = s.take_f64("lambda");
    for (std::size_t l = 0; l < nl; ++l) {
        const MultiquadricLocal& h = f->locals_[l];
        if (h.count == 0) continue;
        std::uint64_t terms = 0;
        for (std::uint32_t r = f->run_first_[l]; r < f->run_first_[l + 1]; ++r) terms += f->runs_[r].count;
        if (terms != h.count)
            s.fail("local_ranges", "local " + std::to_string(l) + " has " + std::to_string(h.count) + " terms, its runs " +
                                       std::to_string(terms));
    }
    check_local_ranges(s, f->locals_, f->lambda_.size());
    return f;
}

}  // namespace meshless
