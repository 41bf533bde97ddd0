// The marching stencils of the scattered-data isosurface (dissertation sections 5.4-5.6): the local
// CGAL Delaunay (statuses for too few, coplanar and duplicate points; positively oriented tetrahedra
// filling the convex hull; deterministic), the domain cover (every point of the data's bounding box
// lies in a tetrahedron that some stencil owns, for uniform, clustered and layered distributions),
// and the seeds of a sampled sphere (near the sphere, normals towards increasing values, every
// direction reached, nothing from a stencil the isovalue does not cross).
#include <catch2/catch.hpp>

#include <cmath>
#include <random>

#include "kernels/barycentric_lattice.hpp"
#include "kernels/field.hpp"
#include "kernels/marching_stencils.hpp"
#include "kernels/scattered_binning_grid.hpp"
#include "kernels/stencil_delaunay.hpp"
#include "kernels/stencil_seeds.hpp"

using namespace meshless;

namespace {

/// |p - centre| as a Field.
class Distance final : public Field {
public:
    explicit Distance(Vec3 c = {0, 0, 0}) : c_(c) {}
    void evaluate(std::span<const Vec3> p, std::span<double> value, std::span<Vec3> grad) const override {
        for (std::size_t i = 0; i < p.size(); ++i) {
            value[i] = norm(p[i] - c_);
            if (!grad.empty()) grad[i] = normalized(p[i] - c_);
        }
    }
    std::array<Vec3, 2> bounds() const override { return {Vec3{-1, -1, -1}, Vec3{1, 1, 1}}; }
    std::string name() const override { return "distance"; }

private:
    Vec3 c_;
};

double tet_volume(const std::array<Vec3, 4>& t) { return dot(t[1] - t[0], cross(t[2] - t[0], t[3] - t[0])) / 6; }

bool in_tet(const std::array<Vec3, 4>& t, const Vec3& q) {
    const double v = tet_volume(t);
    if (v == 0) return false;
    const double eps = -1e-12 * std::abs(v);
    for (int i = 0; i < 4; ++i) {
        std::array<Vec3, 4> s = t;
        s[static_cast<std::size_t>(i)] = q;
        if (tet_volume(s) / (v > 0 ? 1 : -1) < eps) return false;
    }
    return true;
}

std::vector<Vec3> distribution(const std::string& kind, int n, std::mt19937_64& rng) {
    std::uniform_real_distribution<double> u(-1, 1);
    std::normal_distribution<double> g(0, 0.08);
    std::vector<Vec3> p;
    for (int i = 0; i < n; ++i) {
        if (kind == "uniform") p.push_back({u(rng), u(rng), u(rng)});
        else if (kind == "clustered") {
            // 100:1 density contrast: most points in two Gaussian blobs, a sparse uniform background
            if (i % 10 == 0) p.push_back({u(rng), u(rng), u(rng)});
            else {
                const double cx = (i % 2) ? -0.5 : 0.4;
                p.push_back({std::clamp(cx + g(rng), -1.0, 1.0), std::clamp(g(rng), -1.0, 1.0), std::clamp(0.3 + g(rng), -1.0, 1.0)});
            }
        } else {  // layered: dense in x, y; eight z layers
            p.push_back({u(rng), u(rng), -1 + 2.0 * double(i % 8) / 7});
        }
    }
    return p;
}

}  // namespace

TEST_CASE("stencil Delaunay: statuses, orientation, hull volume, determinism", "[kernels][scattered]") {
    std::vector<std::array<std::uint32_t, 4>> tets;
    CHECK(stencil_delaunay(std::vector<Vec3>{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, tets) == DelaunayStatus::too_few);
    CHECK(stencil_delaunay(std::vector<Vec3>{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {0.3, 0.2, 0}}, tets) == DelaunayStatus::flat);
    CHECK(tets.empty());
    CHECK(stencil_delaunay(std::vector<Vec3>{{0, 0, 0}, {0, 0, 0}, {1, 0, 0}, {1, 0, 0}, {0, 1, 0}}, tets) == DelaunayStatus::too_few);
    // a failure is a status with its reason, never a crash or an exception
    std::string why;
    CHECK(stencil_delaunay(std::vector<Vec3>{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {NAN, 0.5, 0.5}}, tets, &why) == DelaunayStatus::failed);
    CHECK(why == "non-finite coordinate");
    CHECK(tets.empty());
    // the unit cube's corners (cospherical) and interior points: the tetrahedra fill the cube
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> u(0, 1);
    std::vector<Vec3> p;
    for (int c = 0; c < 8; ++c) p.push_back({double(c & 1), double(c >> 1 & 1), double(c >> 2 & 1)});
    for (int i = 0; i < 60; ++i) p.push_back({u(rng), u(rng), u(rng)});
    p.push_back(p[10]);  // a duplicate
    REQUIRE(stencil_delaunay(p, tets) == DelaunayStatus::ok);
    double vol = 0;
    for (const auto& t : tets) {
        for (auto i : t) CHECK(i != 68u);  // the duplicate keeps the first vertex
        const double v = tet_volume({p[t[0]], p[t[1]], p[t[2]], p[t[3]]});
        CHECK(v > 0);
        vol += v;
    }
    CHECK(vol == Approx(1.0).epsilon(1e-12));
    std::vector<std::array<std::uint32_t, 4>> again;
    REQUIRE(stencil_delaunay(p, again) == DelaunayStatus::ok);
    CHECK(again == tets);
}

TEST_CASE("marching stencils: alternate centres, every cell in a stencil, owned boxes partition space", "[kernels][scattered]") {
    for (std::int64_t d : {3, 4, 5, 6, 10, 18}) {
        INFO("cells " << d);
        const std::int64_t s = stencil_count(d);
        std::vector<int> in(static_cast<std::size_t>(d), 0);
        for (std::int64_t m = 0; m < s; ++m) {
            const std::int64_t c = stencil_centre(m, d);
            CHECK(c >= 1);
            CHECK(c <= d - 2);
            for (std::int64_t i = c - 1; i <= c + 1; ++i) ++in[static_cast<std::size_t>(i)];
            const auto o = stencil_owned(m, d);
            if (m > 0) CHECK(o[0] == stencil_owned(m - 1, d)[1]);
            CHECK((m == 0 || o[0] >= double(c - 1)));
            CHECK((m + 1 == s || o[1] <= double(c + 2)));
        }
        for (int k : in) CHECK(k >= 1);
        CHECK(std::isinf(stencil_owned(0, d)[0]));
        CHECK(std::isinf(stencil_owned(s - 1, d)[1]));
    }
}

TEST_CASE("marching stencils: the owned tetrahedra cover the bounding box (domain cover)", "[kernels][scattered]") {
    for (const std::string kind : {"uniform", "clustered", "layered"}) {
        INFO(kind);
        std::mt19937_64 rng(kind.size());
        const std::vector<Vec3> pos = distribution(kind, 3000, rng);
        std::vector<double> val(pos.size());
        for (std::size_t i = 0; i < pos.size(); ++i) val[i] = norm(pos[i]);
        const BinningGrid g = make_binning_grid(pos);
        const BinnedPoints b = bin_points(g, pos);
        const Distance f;
        const StencilInput in{g, b, pos, val, f};
        const StencilGrid sg(g.dims);
        std::vector<std::array<Vec3, 4>> all, tets;
        for (std::int64_t s = 0; s < sg.total(); ++s) {
            REQUIRE(stencil_owned_tets(in, s, tets));
            all.insert(all.end(), tets.begin(), tets.end());
        }
        std::uniform_real_distribution<double> u(0, 1);
        int uncovered = 0;
        const int queries = 3000;
        for (int q = 0; q < queries; ++q) {
            const Vec3 lo = g.bounds[0], hi = g.bounds[1];
            const Vec3 x{lo.x + (hi.x - lo.x) * u(rng), lo.y + (hi.y - lo.y) * u(rng), lo.z + (hi.z - lo.z) * u(rng)};
            bool hit = false;
            for (const auto& t : all)
                if (in_tet(t, x)) {
                    hit = true;
                    break;
                }
            uncovered += !hit;
        }
        CHECK(uncovered == 0);
        // the bounding box's corners too
        for (int c = 0; c < 8; ++c) {
            const Vec3 x{(c & 1) ? g.bounds[1].x : g.bounds[0].x, (c & 2) ? g.bounds[1].y : g.bounds[0].y, (c & 4) ? g.bounds[1].z : g.bounds[0].z};
            bool hit = false;
            for (const auto& t : all) hit = hit || in_tet(t, x);
            CHECK(hit);
        }
    }
}

TEST_CASE("stencil seeds of a sampled sphere: near the sphere, oriented to decreasing |p|, all around", "[kernels][scattered]") {
    std::mt19937_64 rng(9);
    std::uniform_real_distribution<double> u(-1, 1);
    std::vector<Vec3> pos;
    for (int i = 0; i < 8000; ++i) pos.push_back({u(rng), u(rng), u(rng)});
    std::vector<double> val(pos.size());
    for (std::size_t i = 0; i < pos.size(); ++i) val[i] = norm(pos[i]);
    const BinningGrid g = make_binning_grid(pos);
    const BinnedPoints b = bin_points(g, pos);
    const Distance f;
    const StencilInput in{g, b, pos, val, f};
    const StencilGrid sg(g.dims);
    const int n = 2;
    const auto lattice = barycentric_lattice(n);
    std::vector<SeedRecord> seeds;
    StencilSeedStats st;
    for (std::int64_t s = 0; s < sg.total(); s += sg.count[0]) stencil_seeds(in, 0.6, n, lattice, s, s + sg.count[0], seeds, st);
    CHECK(st.stencils == sg.total());
    CHECK(st.crossed_stencils > 0);
    CHECK(st.crossed_stencils < st.stencils);
    CHECK(st.delaunay_failures == 0);
    CHECK(st.seeds == static_cast<std::int64_t>(seeds.size()));
    CHECK(st.seeds == st.triangles * 3);
    CHECK(st.regularisation_points > 0);
    REQUIRE(seeds.size() > 1000);
    const double h = g.diagonal();
    int inward = 0;  // VTK's convention: towards decreasing values, |p| grows outwards
    for (const SeedRecord& s : seeds) {
        const Vec3 p{s.pos[0], s.pos[1], s.pos[2]};
        CHECK(std::abs(norm(p) - 0.6) < 0.5 * h);
        CHECK(s.cell_diagonal <= h * (1 + 1e-6));
        CHECK(s.cell_diagonal > 0.3 * h);
        CHECK(s.base_radius > 0);
        inward += dot(Vec3{s.normal[0], s.normal[1], s.normal[2]}, p) < 0;
    }
    CHECK(inward > 0.97 * double(seeds.size()));
    // every direction of the sphere has a seed within a cell
    for (int d = 0; d < 200; ++d) {
        const Vec3 dir = normalized(Vec3{u(rng), u(rng), u(rng)});
        double best = 1e9;
        for (const SeedRecord& s : seeds) best = std::min(best, norm(Vec3{s.pos[0], s.pos[1], s.pos[2]} - dir * 0.6));
        CHECK(best < 0.5 * h);
    }
    // an isovalue that crosses nothing: no tetrahedrization at all
    StencilSeedStats none;
    std::vector<SeedRecord> empty;
    stencil_seeds(in, 5.0, n, lattice, 0, sg.count[0], empty, none);
    CHECK(empty.empty());
    CHECK(none.crossed_stencils == 0);
    CHECK(none.tets == 0);
}
