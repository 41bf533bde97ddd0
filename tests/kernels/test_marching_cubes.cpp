// Tests for kernels/marching_cubes_table.hpp and kernels/marching_cubes.hpp (dissertation §3.6 baseline).
// Oracles: the corner signs of every one of the 256 cases (crossing edges, orientation towards the
// below corner: VTK's convention, normals towards decreasing value), closed-surface topology (every edge shared by two triangles, each directed edge once,
// Euler characteristic 2 for a sphere and 0 for a torus), analytic distance fields, linear fields
// (planar surfaces), brute-force counts of crossing edges and active cells, complement symmetry.
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <random>
#include <set>
#include <tuple>
#include <vector>

#include "kernels/analytic_volumes.hpp"
#include "kernels/errors.hpp"
#include "kernels/marching_cubes.hpp"
#include "kernels/marching_cubes_table.hpp"

using namespace meshless;

namespace {

template <class T, class F>
Volume make_volume(std::array<std::int64_t, 3> dims, SampleType type, F f,
                   std::array<double, 3> origin = {0, 0, 0}, std::array<double, 3> spacing = {1, 1, 1}) {
    GridSpec g;
    g.dims = dims;
    g.origin = origin;
    g.spacing = spacing;
    Volume v(g, type);
    T* p = reinterpret_cast<T*>(v.bytes.data());
    for (std::int64_t k = 0; k < dims[2]; ++k)
        for (std::int64_t j = 0; j < dims[1]; ++j)
            for (std::int64_t i = 0; i < dims[0]; ++i) p[g.index(i, j, k)] = static_cast<T>(f(i, j, k));
    return v;
}

Vec3 vertex(const Mesh& m, std::uint32_t i) { return {m.xyz[3 * i], m.xyz[3 * i + 1], m.xyz[3 * i + 2]}; }
Vec3 vnormal(const Mesh& m, std::uint32_t i) {
    return {m.normals[3 * i], m.normals[3 * i + 1], m.normals[3 * i + 2]};
}
Vec3 tri_cross(const Mesh& m, std::size_t t) {
    const Vec3 a = vertex(m, m.tri[3 * t]), b = vertex(m, m.tri[3 * t + 1]), c = vertex(m, m.tri[3 * t + 2]);
    return cross(b - a, c - a);
}

struct Topology {
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> undirected;  // (min,max) -> uses
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
    bool closed() const {
        for (auto& [e, n] : undirected)
            if (n != 2) return false;
        return true;
    }
    bool oriented() const {
        for (auto& [e, n] : directed)
            if (n != 1) return false;
        return true;
    }
};

Topology topology(const Mesh& m) {
    Topology t;
    for (std::size_t f = 0; f < m.triangle_count(); ++f)
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t a = m.tri[3 * f + k], b = m.tri[3 * f + (k + 1) % 3];
            ++t.directed[{a, b}];
            ++t.undirected[{std::min(a, b), std::max(a, b)}];
        }
    return t;
}

/// Every vertex's link (opposite edges of its triangles) is one closed cycle.
bool vertex_manifold(const Mesh& m) {
    std::vector<std::vector<std::pair<std::uint32_t, std::uint32_t>>> link(m.vertex_count());
    for (std::size_t f = 0; f < m.triangle_count(); ++f)
        for (int k = 0; k < 3; ++k)
            link[m.tri[3 * f + k]].push_back({m.tri[3 * f + (k + 1) % 3], m.tri[3 * f + (k + 2) % 3]});
    for (auto& l : link) {
        if (l.empty()) continue;
        std::map<std::uint32_t, std::uint32_t> next;
        for (auto& [a, b] : l) {
            if (next.count(a)) return false;
            next[a] = b;
        }
        std::uint32_t x = l[0].first;
        std::size_t steps = 0;
        do {
            auto it = next.find(x);
            if (it == next.end()) return false;
            x = it->second;
            ++steps;
        } while (x != l[0].first && steps <= l.size());
        if (steps != l.size()) return false;
    }
    return true;
}

std::int64_t euler(const Mesh& m) {
    const Topology t = topology(m);
    return static_cast<std::int64_t>(m.vertex_count()) - static_cast<std::int64_t>(t.undirected.size()) +
           static_cast<std::int64_t>(m.triangle_count());
}

double signed_volume(const Mesh& m) {
    double v = 0;
    for (std::size_t f = 0; f < m.triangle_count(); ++f)
        v += dot(vertex(m, m.tri[3 * f]), cross(vertex(m, m.tri[3 * f + 1]), vertex(m, m.tri[3 * f + 2])));
    return v / 6.0;
}

Vec3 vector_area(const Mesh& m) {
    Vec3 s;
    for (std::size_t f = 0; f < m.triangle_count(); ++f) s += tri_cross(m, f) * 0.5;
    return s;
}

double corner_value(int cs, int c) { return (cs >> c) & 1 ? 1.0 : -1.0; }

Volume case_volume(int cs, double sign = 1.0) {
    return make_volume<float>({2, 2, 2}, SampleType::f32,
                              [&](auto i, auto j, auto k) { return sign * corner_value(cs, int(i + 2 * j + 4 * k)); });
}

Vec3 corner_pos(int c) { return {double(c & 1), double((c >> 1) & 1), double((c >> 2) & 1)}; }

}  // namespace

TEST_CASE("mc table: triangles use exactly the edges with a sign change", "[mc]") {
    const McTable& t = marching_cubes_table();
    REQUIRE(t.max_triangles <= kMcMaxTriangles);
    for (int cs = 0; cs < 256; ++cs) {
        const McCase& c = t.cases[cs];
        unsigned crossing = 0;
        for (int e = 0; e < 12; ++e) {
            const int a = kMcEdgeCorners[e][0], b = kMcEdgeCorners[e][1];
            REQUIRE(mc_edge_of(a, b) == e);
            if (((cs >> a) & 1) != ((cs >> b) & 1)) crossing |= 1u << e;
        }
        CHECK(c.edge_mask == crossing);
        unsigned used = 0;
        for (int k = 0; k < c.triangle_count; ++k) {
            const int e0 = c.edges[3 * k], e1 = c.edges[3 * k + 1], e2 = c.edges[3 * k + 2];
            CHECK((e0 != e1 && e1 != e2 && e0 != e2));
            used |= (1u << e0) | (1u << e1) | (1u << e2);
        }
        CHECK(used == crossing);
        // a polygon with p vertices gives p-2 triangles: sum over polygons = crossings - 2*polygons
        CHECK(c.triangle_count == __builtin_popcount(crossing) - 2 * c.polygon_count);
        // triangle sides joining two edges of one face are boundary segments (used once); the
        // other sides are interior diagonals (used twice, in opposite directions)
        std::map<std::pair<int, int>, int> sides;
        for (int k = 0; k < c.triangle_count; ++k)
            for (int q = 0; q < 3; ++q) ++sides[{c.edges[3 * k + q], c.edges[3 * k + (q + 1) % 3]}];
        for (auto& [sd, uses] : sides) {
            CHECK(uses == 1);
            const bool reverse = sides.count({sd.second, sd.first}) > 0;
            CHECK(reverse == !mc_edges_share_face(sd.first, sd.second));
        }
    }
}

TEST_CASE("mc: each of the 256 cases in a 2x2x2 volume", "[mc]") {
    for (int cs = 0; cs < 256; ++cs) {
        INFO("case " << cs);
        const Volume v = case_volume(cs);
        McStats st;
        const Mesh m = marching_cubes(v.view(), 0.0, &st);
        const unsigned mask = marching_cubes_table().cases[cs].edge_mask;
        CHECK(st.active_cells == ((cs == 0 || cs == 255) ? 0 : 1));
        CHECK(st.skipped_nonfinite == 0);
        REQUIRE(m.vertex_count() == static_cast<std::size_t>(__builtin_popcount(mask)));
        REQUIRE(m.normals.size() == m.xyz.size());
        // every vertex is the midpoint of a distinct edge with a sign change
        std::vector<int> edge_of_vertex(m.vertex_count(), -1);
        std::set<int> seen;
        for (std::uint32_t i = 0; i < m.vertex_count(); ++i) {
            const Vec3 p = vertex(m, i);
            for (int e = 0; e < 12; ++e) {
                const Vec3 mid = (corner_pos(kMcEdgeCorners[e][0]) + corner_pos(kMcEdgeCorners[e][1])) * 0.5;
                if (norm(p - mid) < 1e-6) edge_of_vertex[i] = e;
            }
            REQUIRE(edge_of_vertex[i] >= 0);
            CHECK((mask >> edge_of_vertex[i]) & 1);
            CHECK(seen.insert(edge_of_vertex[i]).second);
            CHECK(std::abs(norm(vnormal(m, i)) - 1.0) < 1e-5);
        }
        // every vertex normal faces the below end of its edge (VTK: towards decreasing value); every
        // triangle faces the below ends of its three edges on balance (a single one may be
        // perpendicular or slightly behind for a triangle of a non-planar polygon)
        for (std::size_t f = 0; f < m.triangle_count(); ++f) {
            const Vec3 n = normalized(tri_cross(m, f));
            REQUIRE(norm(tri_cross(m, f)) > 1e-6);
            double sum = 0;
            for (int k = 0; k < 3; ++k) {
                const std::uint32_t vi = m.tri[3 * f + k];
                const int e = edge_of_vertex[vi];
                const int a = kMcEdgeCorners[e][0], b = kMcEdgeCorners[e][1];
                const Vec3 down = ((cs >> b) & 1) ? corner_pos(a) - corner_pos(b) : corner_pos(b) - corner_pos(a);
                sum += dot(n, down);
                CHECK(dot(vnormal(m, vi), down) > 0);
            }
            CHECK(sum > 0.5);
        }
    }
}

TEST_CASE("mc: each case embedded in a 4x4x4 volume gives a closed surface facing the low values", "[mc]") {
    for (int cs = 1; cs < 256; ++cs) {
        for (double sign : {1.0, -1.0}) {
            INFO("case " << cs << " sign " << sign);
            // border below (sign=+1) or above (sign=-1); the centre cell carries the case (or its complement)
            const Volume v = make_volume<float>({4, 4, 4}, SampleType::f32, [&](auto i, auto j, auto k) {
                if (i == 0 || j == 0 || k == 0 || i == 3 || j == 3 || k == 3) return -sign;
                return sign * corner_value(cs, int((i - 1) + 2 * (j - 1) + 4 * (k - 1)));
            });
            const Mesh m = marching_cubes(v.view(), 0.0);
            const Topology t = topology(m);
            CHECK(t.closed());
            CHECK(t.oriented());
            CHECK(vertex_manifold(m));
            // normals point towards decreasing value (VTK): out of the above blobs (sign=+1), into
            // the below blobs (sign=-1)
            const double vol = signed_volume(m);
            if (sign > 0) CHECK(vol > 0);
            else CHECK(vol < 0);
        }
    }
}

TEST_CASE("mc: complement symmetry (flipped signs)", "[mc]") {
    const McTable& table = marching_cubes_table();
    for (int cs = 0; cs < 256; ++cs) {
        INFO("case " << cs);
        const Mesh a = marching_cubes(case_volume(cs).view(), 0.0);
        const Mesh b = marching_cubes(case_volume(cs, -1.0).view(), 0.0);  // case 255 - cs
        REQUIRE(a.vertex_count() == b.vertex_count());
        CHECK(a.xyz == b.xyz);  // same crossings, same deterministic vertex order
        for (std::size_t i = 0; i < a.normals.size(); ++i) CHECK(a.normals[i] == -b.normals[i]);
        if (table.cases[cs].ambiguous_faces == 0) {
            // same boundary loops reversed: the vector area (a function of the boundary) flips
            const Vec3 sa = vector_area(a), sb = vector_area(b);
            CHECK(norm(sa + sb) < 1e-6);
            CHECK(table.cases[cs].triangle_count == table.cases[255 - cs].triangle_count);
        }
    }
}

TEST_CASE("mc: sphere distance field is closed, genus 0, accurate", "[mc]") {
    const std::int64_t n = 64;
    const Volume v = make_analytic_volume(AnalyticField::sphere, n);
    const double h = v.grid.spacing[0];
    const double r = 20.0 * h;  // radius 20 voxels
    McStats st;
    const Mesh m = marching_cubes(v.view(), r, &st);
    REQUIRE(m.triangle_count() > 1000);
    CHECK(st.active_cells > 0);
    CHECK(st.skipped_nonfinite == 0);
    const Topology t = topology(m);
    CHECK(t.closed());
    CHECK(t.oriented());
    CHECK(vertex_manifold(m));
    CHECK(euler(m) == 2);
    double area = 0;
    for (std::size_t f = 0; f < m.triangle_count(); ++f) area += 0.5 * norm(tri_cross(m, f));
    const double exact_area = 4.0 * M_PI * r * r;
    CHECK(std::abs(area - exact_area) < 0.01 * exact_area);
    // inward normals (value increases outwards, VTK's normals point to decreasing value): negative
    // enclosed volume ~ -4/3 pi r^3
    const double vol = signed_volume(m);
    CHECK(std::abs(vol + 4.0 / 3.0 * M_PI * r * r * r) < 0.01 * (4.0 / 3.0 * M_PI * r * r * r));
    double max_dist = 0, sum_angle = 0;
    for (std::uint32_t i = 0; i < m.vertex_count(); ++i) {
        const Vec3 p = vertex(m, i);
        max_dist = std::max(max_dist, analytic_distance(AnalyticField::sphere, r, p) / h);
        const double c = std::clamp(dot(vnormal(m, i), -normalized(p)), -1.0, 1.0);
        sum_angle += std::acos(c) * 180.0 / M_PI;
    }
    CHECK(max_dist < 0.05);
    CHECK(sum_angle / static_cast<double>(m.vertex_count()) < 2.0);
}

TEST_CASE("mc: torus has Euler characteristic 0", "[mc]") {
    const Volume v = make_analytic_volume(AnalyticField::torus, 64);
    const double iso = default_iso(AnalyticField::torus);
    const Mesh m = marching_cubes(v.view(), iso);
    const Topology t = topology(m);
    CHECK(t.closed());
    CHECK(t.oriented());
    CHECK(vertex_manifold(m));
    CHECK(euler(m) == 0);
    double max_dist = 0;
    for (std::uint32_t i = 0; i < m.vertex_count(); ++i)
        max_dist = std::max(max_dist, analytic_distance(AnalyticField::torus, iso, vertex(m, i)));
    CHECK(max_dist / v.grid.spacing[0] < 0.1);
}

TEST_CASE("mc: gyroid and Marschner-Lobb vertices lie near the analytic surface", "[mc]") {
    for (AnalyticField f : {AnalyticField::gyroid, AnalyticField::marschner_lobb}) {
        INFO(to_string(f));
        const Volume v = make_analytic_volume(f, 64);
        const double iso = default_iso(f);
        const Mesh m = marching_cubes(v.view(), iso);
        REQUIRE(m.triangle_count() > 1000);
        CHECK(topology(m).oriented());
        double sum = 0;
        for (std::uint32_t i = 0; i < m.vertex_count(); ++i)
            sum += analytic_distance(f, iso, vertex(m, i)) / v.grid.spacing[0];
        const double mean = sum / static_cast<double>(m.vertex_count());
        // gyroid is well resolved; Marschner-Lobb is deliberately near the Nyquist limit
        CHECK(mean < (f == AnalyticField::gyroid ? 0.05 : 0.5));
    }
}

TEST_CASE("mc: random volumes are closed except on the domain boundary", "[mc]") {
    std::mt19937_64 rng(7);
    for (int trial = 0; trial < 40; ++trial) {
        std::uniform_int_distribution<std::int64_t> D(2, 9);
        const std::array<std::int64_t, 3> dims{D(rng), D(rng), D(rng)};
        const bool bytes = trial % 2 == 0;
        std::uniform_int_distribution<int> U8(0, 6);  // few levels: many samples exactly at iso
        std::uniform_real_distribution<float> UF(-1.0f, 1.0f);
        const double iso = bytes ? 3.0 : 0.1;
        const Volume v = bytes ? make_volume<std::uint8_t>(dims, SampleType::u8, [&](auto, auto, auto) { return U8(rng); })
                               : make_volume<float>(dims, SampleType::f32, [&](auto, auto, auto) { return UF(rng); },
                                                    {-3, 1, 2}, {0.5, 1.5, 2.0});
        INFO("trial " << trial << " dims " << dims[0] << "x" << dims[1] << "x" << dims[2]);
        McStats st;
        const Mesh m = marching_cubes(v.view(), iso, &st);
        // brute force: crossing edges (one vertex each) and active cells
        const VolumeView vw = v.view();
        std::int64_t crossings = 0, active = 0;
        auto above = [&](std::int64_t i, std::int64_t j, std::int64_t k) { return vw.at(i, j, k) >= iso; };
        for (std::int64_t k = 0; k < dims[2]; ++k)
            for (std::int64_t j = 0; j < dims[1]; ++j)
                for (std::int64_t i = 0; i < dims[0]; ++i) {
                    if (i + 1 < dims[0] && above(i, j, k) != above(i + 1, j, k)) ++crossings;
                    if (j + 1 < dims[1] && above(i, j, k) != above(i, j + 1, k)) ++crossings;
                    if (k + 1 < dims[2] && above(i, j, k) != above(i, j, k + 1)) ++crossings;
                    if (i + 1 < dims[0] && j + 1 < dims[1] && k + 1 < dims[2]) {
                        int n = 0;
                        for (int c = 0; c < 8; ++c) n += above(i + (c & 1), j + ((c >> 1) & 1), k + (c >> 2));
                        if (n != 0 && n != 8) ++active;
                    }
                }
        CHECK(static_cast<std::int64_t>(m.vertex_count()) == crossings);
        CHECK(st.active_cells == active);
        const Topology t = topology(m);
        CHECK(t.oriented());
        const auto& g = v.grid;
        auto on_same_boundary_plane = [&](const Vec3& a, const Vec3& b) {
            for (int d = 0; d < 3; ++d) {
                const double lo = g.origin[d], hi = g.origin[d] + g.spacing[d] * double(g.dims[d] - 1);
                const double eps = 1e-5 * g.spacing[d];
                if (std::abs(a[d] - lo) < eps && std::abs(b[d] - lo) < eps) return true;
                if (std::abs(a[d] - hi) < eps && std::abs(b[d] - hi) < eps) return true;
            }
            return false;
        };
        for (auto& [e, uses] : t.undirected) {
            if (uses == 2) continue;
            CHECK(uses == 1);
            CHECK(on_same_boundary_plane(vertex(m, e.first), vertex(m, e.second)));
        }
    }
}

TEST_CASE("mc: a linear field gives a planar surface with constant normal", "[mc]") {
    const Vec3 a{0.3, -0.7, 0.45};
    const std::array<double, 3> origin{-2, 1, 0.5}, spacing{0.5, 0.25, 1.0};
    const Volume v = make_volume<float>({17, 23, 11}, SampleType::f32, [&](auto i, auto j, auto k) {
        const Vec3 p{origin[0] + spacing[0] * i, origin[1] + spacing[1] * j, origin[2] + spacing[2] * k};
        return dot(a, p);
    }, origin, spacing);
    const double iso = 0.2;
    const Mesh m = marching_cubes(v.view(), iso);
    REQUIRE(m.triangle_count() > 100);
    const Vec3 an = normalized(a);
    for (std::uint32_t i = 0; i < m.vertex_count(); ++i) {
        CHECK(std::abs(dot(a, vertex(m, i)) - iso) < 1e-5);
        CHECK(dot(vnormal(m, i), -an) > 1 - 1e-5);  // VTK: -grad f
    }
    for (std::size_t f = 0; f < m.triangle_count(); ++f) {
        const Vec3 n = tri_cross(m, f);
        INFO("triangle area " << 0.5 * norm(n));
        if (norm(n) < 1e-4) continue;  // slivers: float rounding dominates their direction
        CHECK(dot(normalized(n), -an) > 1 - 1e-4);
    }
    CHECK(topology(m).oriented());
}

TEST_CASE("mc: cells with NaN or Inf corners are skipped and counted", "[mc]") {
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<float> U(-1, 1);
    std::uniform_int_distribution<int> P(0, 30);
    const std::array<std::int64_t, 3> dims{12, 9, 7};
    Volume v = make_volume<float>(dims, SampleType::f32, [&](auto, auto, auto) {
        const int r = P(rng);
        if (r == 0) return std::numeric_limits<float>::quiet_NaN();
        if (r == 1) return std::numeric_limits<float>::infinity();
        return U(rng);
    });
    McStats st;
    const Mesh m = marching_cubes(v.view(), 0.0, &st);
    std::int64_t bad = 0, active = 0;
    const VolumeView vw = v.view();
    for (std::int64_t k = 0; k + 1 < dims[2]; ++k)
        for (std::int64_t j = 0; j + 1 < dims[1]; ++j)
            for (std::int64_t i = 0; i + 1 < dims[0]; ++i) {
                bool finite = true;
                int n = 0;
                for (int c = 0; c < 8; ++c) {
                    const double x = vw.at(i + (c & 1), j + ((c >> 1) & 1), k + (c >> 2));
                    finite = finite && std::isfinite(x);
                    n += x >= 0.0;
                }
                if (!finite) ++bad;
                else if (n != 0 && n != 8) ++active;
            }
    REQUIRE(bad > 0);
    CHECK(st.skipped_nonfinite == bad);
    CHECK(st.active_cells == active);
    for (float x : m.xyz) CHECK(std::isfinite(x));
    for (float x : m.normals) CHECK(std::isfinite(x));
    CHECK(topology(m).oriented());
    // an all-NaN volume: every cell skipped, no surface
    const Volume nan = make_volume<float>({3, 4, 5}, SampleType::f32,
                                          [](auto, auto, auto) { return std::nanf(""); });
    const Mesh e = marching_cubes(nan.view(), 0.0, &st);
    CHECK(e.triangle_count() == 0);
    CHECK(st.skipped_nonfinite == 2 * 3 * 4);
}

TEST_CASE("mc: native sample types give identical meshes", "[mc]") {
    const std::array<std::int64_t, 3> dims{21, 18, 15};
    auto f = [](auto i, auto j, auto k) {
        const double d = std::sqrt((i - 10.0) * (i - 10.0) + (j - 8.5) * (j - 8.5) + (k - 7.0) * (k - 7.0));
        return std::floor(200.0 - 20.0 * d > 0 ? 200.0 - 20.0 * d : 0.0);
    };
    const Volume vf = make_volume<float>(dims, SampleType::f32, f);
    const Volume vu8 = make_volume<std::uint8_t>(dims, SampleType::u8, f);
    const Volume vu16 = make_volume<std::uint16_t>(dims, SampleType::u16, f);
    const Volume vi16 = make_volume<std::int16_t>(dims, SampleType::i16, f);
    for (double iso : {100.0, 100.5, 0.0, 37.25}) {
        INFO("iso " << iso);
        const Mesh a = marching_cubes(vf.view(), iso);
        for (const Volume* o : {&vu8, &vu16, &vi16}) {
            const Mesh b = marching_cubes(o->view(), iso);
            CHECK(a.xyz == b.xyz);
            CHECK(a.normals == b.normals);
            CHECK(a.tri == b.tri);
        }
    }
    // negative int16 values against float
    const Volume ni = make_volume<std::int16_t>(dims, SampleType::i16, [&](auto i, auto j, auto k) { return f(i, j, k) - 120.0; });
    const Volume nf = make_volume<float>(dims, SampleType::f32, [&](auto i, auto j, auto k) { return f(i, j, k) - 120.0; });
    CHECK(marching_cubes(ni.view(), -30.5).xyz == marching_cubes(nf.view(), -30.5).xyz);
}

TEST_CASE("mc: slabs together reproduce the whole mesh", "[mc]") {
    const Volume v = make_analytic_volume(AnalyticField::gyroid, 40);
    const Mesh whole = marching_cubes(v.view(), 0.1);
    auto tri_set = [](const Mesh& m, std::set<std::array<float, 9>>& out) {
        for (std::size_t f = 0; f < m.triangle_count(); ++f) {
            std::array<float, 9> t{};
            for (int k = 0; k < 3; ++k)
                for (int d = 0; d < 3; ++d) t[3 * k + d] = m.xyz[3 * m.tri[3 * f + k] + d];
            out.insert(t);
        }
    };
    std::set<std::array<float, 9>> a, b;
    tri_set(whole, a);
    std::size_t tris = 0;
    McStats total, st;
    for (std::int64_t k0 : {0, 7, 20, 21, 33}) {
        const std::int64_t k1 = k0 == 0 ? 7 : k0 == 7 ? 20 : k0 == 20 ? 21 : k0 == 21 ? 33 : 39;
        const Mesh s = marching_cubes_slab(v.view(), 0.1, k0, k1, &st);
        tris += s.triangle_count();
        total.active_cells += st.active_cells;
        tri_set(s, b);
    }
    McStats wst;
    marching_cubes(v.view(), 0.1, &wst);
    CHECK(tris == whole.triangle_count());
    CHECK(total.active_cells == wst.active_cells);
    CHECK(a == b);
}

TEST_CASE("mc: degenerate inputs", "[mc]") {
    const Volume flat = make_volume<float>({5, 1, 4}, SampleType::f32, [](auto i, auto, auto) { return double(i); });
    CHECK(marching_cubes(flat.view(), 2.5).triangle_count() == 0);
    const Volume v = make_analytic_volume(AnalyticField::sphere, 8);
    CHECK_THROWS_AS(marching_cubes(v.view(), std::nan("")), InvalidArgument);
    CHECK(marching_cubes(v.view(), 100.0).triangle_count() == 0);   // nothing above
    CHECK(marching_cubes(v.view(), -100.0).triangle_count() == 0);  // everything above
    CHECK(marching_cubes_slab(v.view(), 0.5, 5, 5).triangle_count() == 0);
    const Mesh m = marching_cubes(v.view(), 0.5);
    CHECK(m.memory_bytes() == m.xyz.size() * 4 + m.normals.size() * 4 + m.tri.size() * 4);
}
