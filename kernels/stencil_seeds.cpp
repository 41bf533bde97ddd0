#include "kernels/stencil_seeds.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "kernels/barycentric_lattice.hpp"
#include "kernels/marching_stencils.hpp"
#include "kernels/marching_tetrahedra.hpp"
#include "kernels/multiblock_splat_radius.hpp"
#include "kernels/stencil_delaunay.hpp"
#include "kernels/stencil_regularisation.hpp"

namespace meshless {

namespace {

std::int64_t ns_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now() - t0).count();
}

/// The 27 cells' points of the stencil centred at cell `c`, in stencil-local cell coordinates
/// (cell coordinates minus c - 1), with their values.
struct StencilPoints {
    std::vector<Vec3> local;
    std::vector<double> value;
};

void gather(const StencilInput& in, const RegularisedBlock& reg, const std::array<std::int64_t, 3>& c, StencilPoints& sp) {
    sp.local.clear();
    sp.value.clear();
    const BinningGrid& g = in.grid;
    const Vec3 base{double(c[0] - 1), double(c[1] - 1), double(c[2] - 1)};
    for (std::int64_t k = c[2] - 1; k <= c[2] + 1; ++k)
        for (std::int64_t j = c[1] - 1; j <= c[1] + 1; ++j)
            for (std::int64_t i = c[0] - 1; i <= c[0] + 1; ++i) {
                const auto pts = in.bins.points_of(g.index(i, j, k));
                if (pts.empty()) {
                    sp.local.push_back(Vec3{double(i) + 0.5, double(j) + 0.5, double(k) + 0.5} - base);
                    sp.value.push_back(reg.at(i, j, k));
                    continue;
                }
                for (std::uint32_t p : pts) {
                    sp.local.push_back(g.to_cell_coords(in.pos[p]) - base);
                    sp.value.push_back(in.value[p]);
                }
            }
}

bool straddles(std::span<const double> v, double iso) {
    bool above = false, below = false;
    for (double x : v) {
        if (std::isnan(x)) continue;
        (x >= iso ? above : below) = true;
        if (above && below) return true;
    }
    return false;
}

/// Owned box of the stencil at (sx, sy, sz), in its local cell coordinates.
std::array<std::array<double, 2>, 3> owned_local(const BinningGrid& g, const std::array<std::int64_t, 3>& m,
                                                 const std::array<std::int64_t, 3>& c) {
    std::array<std::array<double, 2>, 3> o{};
    for (std::size_t a = 0; a < 3; ++a) {
        const auto w = stencil_owned(m[a], g.dims[a]);
        o[a] = {w[0] - double(c[a] - 1), w[1] - double(c[a] - 1)};
    }
    return o;
}

bool owns(const std::array<std::array<double, 2>, 3>& o, const std::array<Vec3, 4>& t) {
    for (int a = 0; a < 3; ++a) {
        const double lo = std::min({t[0][a], t[1][a], t[2][a], t[3][a]});
        const double hi = std::max({t[0][a], t[1][a], t[2][a], t[3][a]});
        if (hi < o[static_cast<std::size_t>(a)][0] || lo >= o[static_cast<std::size_t>(a)][1]) return false;
    }
    return true;
}

std::array<std::int64_t, 3> centre_of(const BinningGrid& g, const std::array<std::int64_t, 3>& m) {
    return {stencil_centre(m[0], g.dims[0]), stencil_centre(m[1], g.dims[1]), stencil_centre(m[2], g.dims[2])};
}

}  // namespace

void stencil_seeds(const StencilInput& in, double iso, int n, std::span<const std::array<double, 3>> lattice, std::int64_t s0,
                   std::int64_t s1, std::vector<SeedRecord>& out, StencilSeedStats& st) {
    if (s1 <= s0) return;
    const BinningGrid& g = in.grid;
    const StencilGrid sg(g.dims);
    const auto m0 = sg.coords(s0), m1 = sg.coords(s1 - 1);
    const auto c0 = centre_of(g, m0), c1 = centre_of(g, m1);
    // the row's cells, regularised once for all its stencils
    auto t0 = std::chrono::steady_clock::now();
    RegularisedBlock reg;
    regularise_block(g, in.bins, in.field, {c0[0] - 1, c0[1] - 1, c0[2] - 1}, {c1[0] + 1, c1[1] + 1, c1[2] + 1}, reg, in.coverage);
    st.regularisation_ns += ns_since(t0);
    st.regularisation_points += reg.evaluations;
    st.uncovered_regularisation += reg.uncovered;

    const double diagonal = g.diagonal();
    StencilPoints sp;
    std::vector<std::array<std::uint32_t, 4>> tets;
    std::vector<double> edges;
    std::array<MtTriangle, 2> tri;
    for (std::int64_t s = s0; s < s1; ++s) {
        ++st.stencils;
        const auto m = sg.coords(s);
        const auto c = centre_of(g, m);
        gather(in, reg, c, sp);
        if (!straddles(sp.value, iso)) continue;
        ++st.crossed_stencils;
        st.max_stencil_points = std::max<std::int64_t>(st.max_stencil_points, static_cast<std::int64_t>(sp.local.size()));
        t0 = std::chrono::steady_clock::now();
        const DelaunayStatus ds = stencil_delaunay(sp.local, tets);
        st.delaunay_ns += ns_since(t0);
        if (ds != DelaunayStatus::ok) {
            ++st.delaunay_failures;
            continue;
        }
        st.tets += static_cast<std::int64_t>(tets.size());
        const auto own = owned_local(g, m, c);
        const Vec3 base{double(c[0] - 1), double(c[1] - 1), double(c[2] - 1)};
        auto world = [&](const Vec3& l) {
            return Vec3{g.origin.x + (l.x + base.x) * g.cell.x, g.origin.y + (l.y + base.y) * g.cell.y, g.origin.z + (l.z + base.z) * g.cell.z};
        };
        // the local scale l of the Newton tolerance and travel limit (section 4.4's cell diagonal)
        edges.clear();
        for (const auto& t : tets)
            for (int a = 0; a < 4; ++a)
                for (int b2 = a + 1; b2 < 4; ++b2) {
                    const Vec3 e = sp.local[t[static_cast<std::size_t>(a)]] - sp.local[t[static_cast<std::size_t>(b2)]];
                    edges.push_back(norm(Vec3{e.x * g.cell.x, e.y * g.cell.y, e.z * g.cell.z}));
                }
        std::nth_element(edges.begin(), edges.begin() + static_cast<std::ptrdiff_t>(edges.size() / 2), edges.end());
        const double scale = std::min(diagonal, 2.0 * edges[edges.size() / 2]);
        for (const auto& t : tets) {
            const std::array<Vec3, 4> p{sp.local[t[0]], sp.local[t[1]], sp.local[t[2]], sp.local[t[3]]};
            if (!owns(own, p)) continue;
            ++st.owned_tets;
            const std::array<double, 4> v{sp.value[t[0]], sp.value[t[1]], sp.value[t[2]], sp.value[t[3]]};
            if (!(std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]) && std::isfinite(v[3]))) {
                ++st.nonfinite_tets;
                continue;
            }
            const std::array<Vec3, 4> pw{world(p[0]), world(p[1]), world(p[2]), world(p[3])};
            const int nt = marching_tetrahedron(pw, v, iso, tri);
            for (int q = 0; q < nt; ++q) {
                const MtTriangle& T = tri[static_cast<std::size_t>(q)];
                const Vec3 nrm = cross(T[1] - T[0], T[2] - T[0]);
                const double area = 0.5 * norm(nrm);
                if (!(area > 0) || !std::isfinite(area)) {
                    ++st.zero_area_triangles;
                    continue;
                }
                ++st.triangles;
                const Vec3 un = nrm * (0.5 / area);
                const auto base_radius = static_cast<float>(lattice_base_radius(area, n));
                for (const auto& w : lattice) {
                    const Vec3 x = barycentric_point(w, T[0], T[1], T[2]);
                    SeedRecord r{};
                    r.pos[0] = static_cast<float>(x.x);
                    r.pos[1] = static_cast<float>(x.y);
                    r.pos[2] = static_cast<float>(x.z);
                    r.normal[0] = static_cast<float>(un.x);
                    r.normal[1] = static_cast<float>(un.y);
                    r.normal[2] = static_cast<float>(un.z);
                    r.value = static_cast<float>(iso);
                    r.base_radius = base_radius;
                    r.cell_diagonal = static_cast<float>(scale);
                    r.block = 0;
                    out.push_back(r);
                    ++st.seeds;
                }
            }
        }
    }
}

bool stencil_owned_tets(const StencilInput& in, std::int64_t s, std::vector<std::array<Vec3, 4>>& out,
                        std::vector<std::array<double, 4>>* values) {
    out.clear();
    if (values) values->clear();
    const BinningGrid& g = in.grid;
    const StencilGrid sg(g.dims);
    const auto m = sg.coords(s);
    const auto c = centre_of(g, m);
    RegularisedBlock reg;
    regularise_block(g, in.bins, in.field, {c[0] - 1, c[1] - 1, c[2] - 1}, {c[0] + 1, c[1] + 1, c[2] + 1}, reg, in.coverage);
    StencilPoints sp;
    gather(in, reg, c, sp);
    std::vector<std::array<std::uint32_t, 4>> tets;
    if (stencil_delaunay(sp.local, tets) != DelaunayStatus::ok) return false;
    const auto own = owned_local(g, m, c);
    const Vec3 base{double(c[0] - 1), double(c[1] - 1), double(c[2] - 1)};
    for (const auto& t : tets) {
        const std::array<Vec3, 4> p{sp.local[t[0]], sp.local[t[1]], sp.local[t[2]], sp.local[t[3]]};
        if (!owns(own, p)) continue;
        std::array<Vec3, 4> w;
        for (int i = 0; i < 4; ++i) {
            const Vec3& l = p[static_cast<std::size_t>(i)];
            w[static_cast<std::size_t>(i)] = {g.origin.x + (l.x + base.x) * g.cell.x, g.origin.y + (l.y + base.y) * g.cell.y,
                                              g.origin.z + (l.z + base.z) * g.cell.z};
        }
        out.push_back(w);
        if (values) values->push_back({sp.value[t[0]], sp.value[t[1]], sp.value[t[2]], sp.value[t[3]]});
    }
    return true;
}

}  // namespace meshless
