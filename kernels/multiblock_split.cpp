#include "kernels/multiblock_split.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "kernels/errors.hpp"

namespace meshless {

namespace {

using I64 = std::int64_t;

int longest_axis(const GridSpec& g) {
    int a = 0;
    double best = -1;
    for (int k = 0; k < 3; ++k) {
        const double e = static_cast<double>(g.dims[k] - 1) * g.spacing[k];
        if (e > best) best = e, a = k;
    }
    return a;
}

Vec3 node_world(const GridSpec& g, double i, double j, double k) {
    return {g.origin[0] + i * g.spacing[0], g.origin[1] + j * g.spacing[1], g.origin[2] + k * g.spacing[2]};
}

/// The volume's own nodes lo..hi (inclusive) with a stride per axis.
StructuredBlock nodes_block(const VolumeView& v, std::array<I64, 3> lo, std::array<I64, 3> hi, std::array<I64, 3> stride,
                            std::string name) {
    StructuredBlock b;
    b.name = std::move(name);
    for (int a = 0; a < 3; ++a) b.dims[a] = (hi[a] - lo[a]) / stride[a] + 1;
    b.node.reserve(static_cast<std::size_t>(b.node_count()));
    b.value.reserve(static_cast<std::size_t>(b.node_count()));
    for (I64 k = 0; k < b.dims[2]; ++k)
        for (I64 j = 0; j < b.dims[1]; ++j)
            for (I64 i = 0; i < b.dims[0]; ++i) {
                const I64 gi = lo[0] + i * stride[0], gj = lo[1] + j * stride[1], gk = lo[2] + k * stride[2];
                b.node.push_back(node_world(v.grid, static_cast<double>(gi), static_cast<double>(gj), static_cast<double>(gk)));
                b.value.push_back(v.at(gi, gj, gk));
            }
    return b;
}

/// A lattice of `dims` nodes spanning the world box [lo, hi], values trilinear from the volume.
StructuredBlock lattice_block(const VolumeView& v, const Vec3& lo, const Vec3& hi, std::array<I64, 3> dims,
                              std::string name) {
    StructuredBlock b;
    b.name = std::move(name);
    b.dims = dims;
    b.node.reserve(static_cast<std::size_t>(b.node_count()));
    b.value.reserve(static_cast<std::size_t>(b.node_count()));
    for (I64 k = 0; k < dims[2]; ++k)
        for (I64 j = 0; j < dims[1]; ++j)
            for (I64 i = 0; i < dims[0]; ++i) {
                const double u = static_cast<double>(i) / static_cast<double>(dims[0] - 1);
                const double w1 = static_cast<double>(j) / static_cast<double>(dims[1] - 1);
                const double w2 = static_cast<double>(k) / static_cast<double>(dims[2] - 1);
                // exact end points: the last node is the box corner itself
                const Vec3 p{i == dims[0] - 1 ? hi.x : lo.x + u * (hi.x - lo.x),
                             j == dims[1] - 1 ? hi.y : lo.y + w1 * (hi.y - lo.y),
                             k == dims[2] - 1 ? hi.z : lo.z + w2 * (hi.z - lo.z)};
                b.node.push_back(p);
                b.value.push_back(sample_trilinear(v, p));
            }
    return b;
}

/// Cell ranges [lo_b, hi_b] along the split axis for K blocks sharing `ov` cell layers.
std::vector<std::array<I64, 2>> overlapping_ranges(I64 cells, int k, int ov) {
    std::vector<std::array<I64, 2>> r;
    for (int b = 0; b < k; ++b) {
        const I64 t0 = static_cast<I64>(std::llround(static_cast<double>(b) * static_cast<double>(cells) / k));
        const I64 t1 = static_cast<I64>(std::llround(static_cast<double>(b + 1) * static_cast<double>(cells) / k));
        r.push_back({std::max<I64>(0, t0 - ov / 2), std::min<I64>(cells, t1 + (ov + 1) / 2)});
    }
    return r;
}

void check_volume(const VolumeView& v) {
    for (int a = 0; a < 3; ++a)
        if (v.grid.dims[a] < 3)
            throw InvalidArgument("split: the volume needs at least 3 nodes along every axis (dims " +
                                  std::to_string(v.grid.dims[0]) + "x" + std::to_string(v.grid.dims[1]) + "x" +
                                  std::to_string(v.grid.dims[2]) + ")");
    if (!v.data) throw InvalidArgument("split: empty volume");
}

}  // namespace

const char* to_string(SplitLayout l) {
    switch (l) {
        case SplitLayout::overlapping: return "overlapping";
        case SplitLayout::semi_conforming: return "semi-conforming";
        case SplitLayout::non_conforming: return "non-conforming";
        case SplitLayout::rotated: return "rotated";
        case SplitLayout::amr: break;
    }
    return "amr";
}

std::optional<SplitLayout> parse_split_layout(std::string_view s) {
    for (SplitLayout l : {SplitLayout::overlapping, SplitLayout::semi_conforming, SplitLayout::non_conforming,
                          SplitLayout::rotated, SplitLayout::amr})
        if (s == to_string(l)) return l;
    return std::nullopt;
}

double sample_trilinear(const VolumeView& v, const Vec3& world) {
    const GridSpec& g = v.grid;
    double f[3];
    I64 i0[3];
    for (int a = 0; a < 3; ++a) {
        const double c = (world[a] - g.origin[a]) / g.spacing[a];
        const double cmax = static_cast<double>(g.dims[a] - 1);
        const double cc = std::clamp(std::isfinite(c) ? c : 0.0, 0.0, cmax);
        I64 i = static_cast<I64>(std::floor(cc));
        if (i >= g.dims[a] - 1) i = std::max<I64>(0, g.dims[a] - 2);
        i0[a] = i;
        f[a] = g.dims[a] > 1 ? cc - static_cast<double>(i) : 0.0;
    }
    double r = 0;
    for (int c = 0; c < 8; ++c) {
        const I64 di = c & 1, dj = (c >> 1) & 1, dk = (c >> 2) & 1;
        const double w = (di ? f[0] : 1 - f[0]) * (dj ? f[1] : 1 - f[1]) * (dk ? f[2] : 1 - f[2]);
        if (w == 0) continue;
        r += w * v.at(std::min(i0[0] + di, g.dims[0] - 1), std::min(i0[1] + dj, g.dims[1] - 1),
                      std::min(i0[2] + dk, g.dims[2] - 1));
    }
    return r;
}

Volume resample_volume(const VolumeView& v, I64 n) {
    if (n < 2 || n > 4096) throw InvalidArgument("resample: expected 2..4096 nodes along the longest axis, got " + std::to_string(n));
    check_volume(v);
    const GridSpec& g = v.grid;
    const int la = longest_axis(g);
    const double ext_l = static_cast<double>(g.dims[la] - 1) * g.spacing[la];
    GridSpec out;
    out.origin = g.origin;
    for (int a = 0; a < 3; ++a) {
        const double ext = static_cast<double>(g.dims[a] - 1) * g.spacing[a];
        const I64 cells = a == la ? n - 1 : std::max<I64>(1, std::llround(static_cast<double>(n - 1) * ext / ext_l));
        out.dims[a] = cells + 1;
        out.spacing[a] = ext / static_cast<double>(cells);
    }
    if (out.dims[0] * out.dims[1] > (std::int64_t{1} << 30) / out.dims[2])
        throw InvalidArgument("resample: " + std::to_string(out.dims[0]) + "x" + std::to_string(out.dims[1]) + "x" +
                              std::to_string(out.dims[2]) + " nodes would exceed 2^30 samples");
    Volume r(out, SampleType::f32);
    float* d = reinterpret_cast<float*>(r.bytes.data());
    for (I64 k = 0; k < out.dims[2]; ++k)
        for (I64 j = 0; j < out.dims[1]; ++j)
            for (I64 i = 0; i < out.dims[0]; ++i)
                d[out.index(i, j, k)] = static_cast<float>(sample_trilinear(
                    v, node_world(out, static_cast<double>(i), static_cast<double>(j), static_cast<double>(k))));
    return r;
}

Multiblock split_volume(const VolumeView& v, SplitLayout layout, const SplitParams& p, const std::string& value_name) {
    check_volume(v);
    if (layout == SplitLayout::amr) return amr_to_multiblock(split_amr(v, {}, value_name));
    const GridSpec& g = v.grid;
    const int A = longest_axis(g);
    const I64 CA = g.dims[A] - 1;
    const std::array<I64, 3> C{g.dims[0] - 1, g.dims[1] - 1, g.dims[2] - 1};
    Multiblock mb;
    mb.value_name = value_name;
    mb.format = "split";
    const auto axis_name = [&](int b) { return std::string("block ") + std::to_string(b); };
    switch (layout) {
        case SplitLayout::overlapping:
        case SplitLayout::rotated: {
            if (p.blocks < 1) throw InvalidArgument("split: --blocks must be >= 1");
            if (p.overlap < 0) throw InvalidArgument("split: --overlap must be >= 0");
            if (p.blocks > 1 && 2 * static_cast<I64>(p.blocks) > CA)
                throw InvalidArgument("split: " + std::to_string(p.blocks) + " blocks need at least " +
                                      std::to_string(2 * p.blocks) + " cells along the longest axis (it has " +
                                      std::to_string(CA) + ")");
            if (p.blocks > 1 && p.overlap >= CA)
                throw InvalidArgument("split: --overlap " + std::to_string(p.overlap) + " is not below the " +
                                      std::to_string(CA) + " cells of the longest axis");
            if (!(std::abs(p.twist_deg) < 45)) throw InvalidArgument("split: the twist must be below 45 degrees");
            const auto ranges = overlapping_ranges(CA, p.blocks, p.overlap);
            for (int b = 0; b < p.blocks; ++b) {
                std::array<I64, 3> lo{0, 0, 0}, hi = C;
                lo[A] = ranges[b][0];
                hi[A] = ranges[b][1];
                if (layout == SplitLayout::overlapping) {
                    mb.blocks.push_back(nodes_block(v, lo, hi, {1, 1, 1}, axis_name(b)));
                    continue;
                }
                const Vec3 wlo = node_world(g, static_cast<double>(lo[0]), static_cast<double>(lo[1]), static_cast<double>(lo[2]));
                const Vec3 whi = node_world(g, static_cast<double>(hi[0]), static_cast<double>(hi[1]), static_cast<double>(hi[2]));
                std::array<I64, 3> dims{};
                for (int a = 0; a < 3; ++a)
                    dims[a] = std::max<I64>(1, std::llround(0.8 * static_cast<double>(hi[a] - lo[a]))) + 1;
                StructuredBlock blk;
                blk.name = axis_name(b);
                blk.dims = dims;
                const int a1 = (A + 1) % 3, a2 = (A + 2) % 3;
                const double c1 = 0.5 * (wlo[a1] + whi[a1]), c2 = 0.5 * (wlo[a2] + whi[a2]);
                const double sign = b % 2 == 0 ? 1.0 : -1.0;
                const double twist = sign * p.twist_deg * std::numbers::pi / 180.0;
                for (I64 k = 0; k < dims[2]; ++k)
                    for (I64 j = 0; j < dims[1]; ++j)
                        for (I64 i = 0; i < dims[0]; ++i) {
                            const double t[3] = {static_cast<double>(i) / static_cast<double>(dims[0] - 1),
                                                 static_cast<double>(j) / static_cast<double>(dims[1] - 1),
                                                 static_cast<double>(k) / static_cast<double>(dims[2] - 1)};
                            double q[3];
                            for (int a = 0; a < 3; ++a) q[a] = wlo[a] + t[a] * (whi[a] - wlo[a]);
                            const double ang = twist * std::sin(std::numbers::pi * t[0]) *
                                               std::sin(std::numbers::pi * t[1]) * std::sin(std::numbers::pi * t[2]);
                            const double x = q[a1] - c1, y = q[a2] - c2;
                            const double cs = std::cos(ang), sn = std::sin(ang);
                            q[a1] = std::clamp(c1 + cs * x - sn * y, wlo[a1], whi[a1]);
                            q[a2] = std::clamp(c2 + sn * x + cs * y, wlo[a2], whi[a2]);
                            const Vec3 pos{q[0], q[1], q[2]};
                            blk.node.push_back(pos);
                            blk.value.push_back(sample_trilinear(v, pos));
                        }
                mb.blocks.push_back(std::move(blk));
            }
            break;
        }
        case SplitLayout::semi_conforming:
        case SplitLayout::non_conforming: {
            if (CA < 4) throw InvalidArgument("split: " + std::string(to_string(layout)) +
                                              " needs at least 4 cells along the longest axis");
            const I64 m = 2 * (CA / 4);
            std::array<I64, 3> lo{0, 0, 0}, hi = C;
            hi[A] = m;
            mb.blocks.push_back(nodes_block(v, lo, hi, {1, 1, 1}, "block 0 (full resolution)"));
            if (layout == SplitLayout::semi_conforming) {
                std::array<I64, 3> lo1{0, 0, 0}, hi1{};
                for (int a = 0; a < 3; ++a) hi1[a] = 2 * (C[a] / 2);
                lo1[A] = m;
                hi1[A] = m + 2 * ((CA - m) / 2);
                mb.blocks.push_back(nodes_block(v, lo1, hi1, {2, 2, 2}, "block 1 (half resolution)"));
            } else {
                std::array<I64, 3> dims{};
                for (int a = 0; a < 3; ++a) {
                    const I64 cells = a == A ? CA - m : C[a];
                    dims[a] = std::max<I64>(1, std::llround(static_cast<double>(cells) / 1.5)) + 1;
                }
                std::array<double, 3> l{0, 0, 0};
                l[A] = static_cast<double>(m);
                const Vec3 wlo = node_world(g, l[0], l[1], l[2]);
                const Vec3 whi = node_world(g, static_cast<double>(C[0]), static_cast<double>(C[1]), static_cast<double>(C[2]));
                mb.blocks.push_back(lattice_block(v, wlo, whi, dims, "block 1 (resampled, 1.5x coarser)"));
            }
            break;
        }
        case SplitLayout::amr: break;
    }
    return mb;
}

AmrHierarchy split_amr(const VolumeView& v, const AmrParams& p, const std::string& value_name) {
    check_volume(v);
    if (p.tile < 2) throw InvalidArgument("amr: the tile must be at least 2 cells");
    const GridSpec& g = v.grid;
    std::array<I64, 3> F{};
    for (int a = 0; a < 3; ++a) {
        F[a] = 4 * ((g.dims[a] - 1) / 4);
        if (F[a] < 4) throw InvalidArgument("amr: the volume needs at least 5 nodes along every axis");
    }
    AmrHierarchy h;
    h.value_name = value_name;
    h.origin = g.origin;
    for (int a = 0; a < 3; ++a) h.spacing0[a] = 4 * g.spacing[a];
    // level 2 (finest) cell values: the mean of the 8 corners
    std::vector<double> fine(static_cast<std::size_t>(F[0] * F[1] * F[2]));
    const auto fidx = [&](I64 i, I64 j, I64 k) { return static_cast<std::size_t>(i + F[0] * (j + F[1] * k)); };
    for (I64 k = 0; k < F[2]; ++k)
        for (I64 j = 0; j < F[1]; ++j)
            for (I64 i = 0; i < F[0]; ++i) {
                double s = 0;
                for (int c = 0; c < 8; ++c) s += v.at(i + (c & 1), j + ((c >> 1) & 1), k + ((c >> 2) & 1));
                fine[fidx(i, j, k)] = s / 8;
            }
    // values and grown ranges of a level-l cell (scale s = 2^(2-l) finest cells per edge)
    const auto cell_mean = [&](int level, I64 i, I64 j, I64 k) {
        const I64 s = I64{1} << (2 - level);
        double sum = 0;
        for (I64 z = k * s; z < (k + 1) * s; ++z)
            for (I64 y = j * s; y < (j + 1) * s; ++y)
                for (I64 x = i * s; x < (i + 1) * s; ++x) sum += fine[fidx(x, y, z)];
        return sum / static_cast<double>(s * s * s);
    };
    const auto crosses = [&](int level, I64 i, I64 j, I64 k, double iso) {
        const I64 s = I64{1} << (2 - level);
        double lo = INFINITY, hi = -INFINITY;
        for (I64 z = std::max<I64>(0, k * s - 1); z < std::min(F[2], (k + 1) * s + 1); ++z)
            for (I64 y = std::max<I64>(0, j * s - 1); y < std::min(F[1], (j + 1) * s + 1); ++y)
                for (I64 x = std::max<I64>(0, i * s - 1); x < std::min(F[0], (i + 1) * s + 1); ++x) {
                    const double f = fine[fidx(x, y, z)];
                    lo = std::min(lo, f), hi = std::max(hi, f);
                }
        return lo <= iso && iso <= hi;
    };
    const auto make_box = [&](int level, std::array<I64, 3> lo, std::array<I64, 3> hi) {
        AmrBox b;
        b.level = level;
        b.lo = lo;
        b.hi = hi;
        const auto n = b.cells();
        b.value.reserve(static_cast<std::size_t>(n[0] * n[1] * n[2]));
        for (I64 k = lo[2]; k <= hi[2]; ++k)
            for (I64 j = lo[1]; j <= hi[1]; ++j)
                for (I64 i = lo[0]; i <= hi[0]; ++i) b.value.push_back(cell_mean(level, i, j, k));
        return b;
    };
    h.boxes.push_back(make_box(0, {0, 0, 0}, {F[0] / 4 - 1, F[1] / 4 - 1, F[2] / 4 - 1}));
    if (!p.iso) {
        std::array<I64, 3> lo1{}, hi1{}, lo2{}, hi2{};
        for (int a = 0; a < 3; ++a) {
            const I64 l = 4 * ((F[a] / 4) / 4), u = 4 * ((3 * F[a] / 4 + 3) / 4);  // finest cells [l, u)
            lo1[a] = l / 2, hi1[a] = u / 2 - 1;
            const I64 w = u - l;
            const I64 l2 = l + 2 * ((w / 4) / 2), u2 = u - 2 * ((w / 4) / 2);
            lo2[a] = l2, hi2[a] = u2 - 1;
        }
        h.boxes.push_back(make_box(1, lo1, hi1));
        h.boxes.push_back(make_box(2, lo2, hi2));
        return h;
    }
    const double iso = *p.iso;
    // refinement of level l (0, 1) into boxes of level l+1; `allowed` = cells of level l that lie in
    // level-l boxes (everything for level 0)
    std::vector<std::uint8_t> allowed;  // level-1 cells inside level-1 boxes
    for (int level = 0; level < 2; ++level) {
        const I64 s = I64{1} << (2 - level);
        const std::array<I64, 3> n{F[0] / s, F[1] / s, F[2] / s};
        const auto li = [&](I64 i, I64 j, I64 k) { return static_cast<std::size_t>(i + n[0] * (j + n[1] * k)); };
        std::vector<std::uint8_t> flag(static_cast<std::size_t>(n[0] * n[1] * n[2]), 0), grown(flag.size(), 0);
        for (I64 k = 0; k < n[2]; ++k)
            for (I64 j = 0; j < n[1]; ++j)
                for (I64 i = 0; i < n[0]; ++i)
                    if ((level == 0 || allowed[li(i, j, k)]) && crosses(level, i, j, k, iso)) flag[li(i, j, k)] = 1;
        for (I64 k = 0; k < n[2]; ++k)
            for (I64 j = 0; j < n[1]; ++j)
                for (I64 i = 0; i < n[0]; ++i) {
                    if (!flag[li(i, j, k)]) continue;
                    for (I64 z = std::max<I64>(0, k - 1); z <= std::min(n[2] - 1, k + 1); ++z)
                        for (I64 y = std::max<I64>(0, j - 1); y <= std::min(n[1] - 1, j + 1); ++y)
                            for (I64 x = std::max<I64>(0, i - 1); x <= std::min(n[0] - 1, i + 1); ++x)
                                if (level == 0 || allowed[li(x, y, z)]) grown[li(x, y, z)] = 1;
                }
        const I64 t = p.tile;
        std::vector<std::uint8_t> next_allowed;
        std::array<I64, 3> n1{2 * n[0], 2 * n[1], 2 * n[2]};
        if (level == 0) next_allowed.assign(static_cast<std::size_t>(n1[0] * n1[1] * n1[2]), 0);
        for (I64 tk = 0; tk < n[2]; tk += t)
            for (I64 tj = 0; tj < n[1]; tj += t)
                for (I64 ti = 0; ti < n[0]; ti += t) {
                    const std::array<I64, 3> lo{ti, tj, tk},
                        hi{std::min(n[0], ti + t) - 1, std::min(n[1], tj + t) - 1, std::min(n[2], tk + t) - 1};
                    bool any = false;
                    for (I64 k = lo[2]; k <= hi[2] && !any; ++k)
                        for (I64 j = lo[1]; j <= hi[1] && !any; ++j)
                            for (I64 i = lo[0]; i <= hi[0] && !any; ++i) any = grown[li(i, j, k)] != 0;
                    if (!any) continue;
                    const std::array<I64, 3> rlo{2 * lo[0], 2 * lo[1], 2 * lo[2]},
                        rhi{2 * hi[0] + 1, 2 * hi[1] + 1, 2 * hi[2] + 1};
                    h.boxes.push_back(make_box(level + 1, rlo, rhi));
                    if (level == 0)
                        for (I64 k = rlo[2]; k <= rhi[2]; ++k)
                            for (I64 j = rlo[1]; j <= rhi[1]; ++j)
                                for (I64 i = rlo[0]; i <= rhi[0]; ++i)
                                    next_allowed[static_cast<std::size_t>(i + n1[0] * (j + n1[1] * k))] = 1;
                }
        if (level == 0) allowed = std::move(next_allowed);
    }
    return h;
}

Multiblock amr_to_multiblock(const AmrHierarchy& h) {
    Multiblock mb;
    mb.value_name = h.value_name;
    mb.format = "vthb";
    std::vector<int> per_level(static_cast<std::size_t>(h.levels), 0);
    for (const AmrBox& box : h.boxes) {
        StructuredBlock b;
        const int idx = box.level < h.levels ? per_level[static_cast<std::size_t>(box.level)]++ : 0;
        b.name = "level " + std::to_string(box.level) + " box " + std::to_string(idx);
        b.level = box.level;
        b.cell_centred = true;
        b.dims = box.cells();
        b.value = box.value;
        const auto s = h.spacing(box.level);
        b.node.reserve(box.value.size());
        for (std::int64_t k = 0; k < b.dims[2]; ++k)
            for (std::int64_t j = 0; j < b.dims[1]; ++j)
                for (std::int64_t i = 0; i < b.dims[0]; ++i)
                    b.node.push_back({h.origin[0] + (static_cast<double>(box.lo[0] + i) + 0.5) * s[0],
                                      h.origin[1] + (static_cast<double>(box.lo[1] + j) + 0.5) * s[1],
                                      h.origin[2] + (static_cast<double>(box.lo[2] + k) + 0.5) * s[2]});
        mb.blocks.push_back(std::move(b));
    }
    return mb;
}

}  // namespace meshless
