// Marching tetrahedra (dissertation section 5.6) against brute force: for every one of the 16
// inside/outside cases on random tetrahedra, the triangles' corners are exactly the crossings of the
// linear interpolant along the edges (found by bisection), their total area is the area of the
// convex crossing polygon, the interpolant equals iso at their centroids, and every normal points to
// decreasing values (against the interpolant's gradient, VTK's convention), whatever the
// tetrahedron's orientation.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <random>

#include "kernels/marching_tetrahedra.hpp"

using namespace meshless;

namespace {

/// Barycentric solve: gradient of the linear interpolant of v over tetrahedron p.
Vec3 linear_gradient(const std::array<Vec3, 4>& p, const std::array<double, 4>& v) {
    const Vec3 e1 = p[1] - p[0], e2 = p[2] - p[0], e3 = p[3] - p[0];
    const double det = dot(e1, cross(e2, e3));
    // g . e_i = v_i - v_0  =>  g = sum (v_i - v_0) * (dual basis)
    const Vec3 d1 = cross(e2, e3) * (1 / det), d2 = cross(e3, e1) * (1 / det), d3 = cross(e1, e2) * (1 / det);
    return d1 * (v[1] - v[0]) + d2 * (v[2] - v[0]) + d3 * (v[3] - v[0]);
}

double interp(const std::array<Vec3, 4>& p, const std::array<double, 4>& v, const Vec3& x) {
    return v[0] + dot(linear_gradient(p, v), x - p[0]);
}

double polygon_area(std::vector<Vec3> q, const Vec3& nrm) {
    Vec3 c{0, 0, 0};
    for (const Vec3& x : q) c += x;
    c = c * (1.0 / double(q.size()));
    const Vec3 u = normalized(q[0] - c), w = cross(normalized(nrm), u);
    std::sort(q.begin(), q.end(), [&](const Vec3& a, const Vec3& b) {
        return std::atan2(dot(a - c, w), dot(a - c, u)) < std::atan2(dot(b - c, w), dot(b - c, u));
    });
    double area = 0;
    for (std::size_t i = 0; i < q.size(); ++i) area += 0.5 * norm(cross(q[i] - c, q[(i + 1) % q.size()] - c));
    return area;
}

}  // namespace

TEST_CASE("marching tetrahedra: every case against brute force", "[kernels][scattered]") {
    std::mt19937_64 rng(42);
    std::uniform_real_distribution<double> u(-1, 1);
    const double iso = 0.3;
    int checked = 0;
    for (int trial = 0; trial < 400; ++trial) {
        const int mask = trial % 16;
        std::array<Vec3, 4> p;
        for (auto& x : p) x = {u(rng), u(rng), u(rng)};
        if (std::abs(dot(p[1] - p[0], cross(p[2] - p[0], p[3] - p[0]))) < 1e-3) continue;
        std::array<double, 4> v;
        for (int i = 0; i < 4; ++i) v[static_cast<std::size_t>(i)] = (mask >> i & 1) ? iso + 0.05 + std::abs(u(rng)) : iso - 0.05 - std::abs(u(rng));
        if (trial % 5 == 0) v[0] = (mask & 1) ? iso : v[0];  // a vertex exactly at iso counts as inside
        std::array<MtTriangle, 2> tri;
        const int nt = marching_tetrahedron(p, v, iso, tri);
        // brute force: bisection along the edges whose ends straddle iso
        std::vector<Vec3> cross_pts;
        for (int a = 0; a < 4; ++a)
            for (int b = a + 1; b < 4; ++b) {
                const bool ia = v[static_cast<std::size_t>(a)] >= iso, ib = v[static_cast<std::size_t>(b)] >= iso;
                if (ia == ib) continue;
                double lo = 0, hi = 1;
                for (int it = 0; it < 80; ++it) {
                    const double m = 0.5 * (lo + hi);
                    const double f = v[static_cast<std::size_t>(a)] + m * (v[static_cast<std::size_t>(b)] - v[static_cast<std::size_t>(a)]);
                    ((f >= iso) == ia ? lo : hi) = m;
                }
                cross_pts.push_back(p[static_cast<std::size_t>(a)] + (p[static_cast<std::size_t>(b)] - p[static_cast<std::size_t>(a)]) * (0.5 * (lo + hi)));
            }
        const int inside = std::popcount(static_cast<unsigned>(mask));
        INFO("mask " << mask);
        if (inside == 0 || inside == 4) {
            CHECK(nt == 0);
            CHECK(cross_pts.empty());
            continue;
        }
        REQUIRE(nt == (cross_pts.size() == 4 ? 2 : 1));
        const Vec3 g = linear_gradient(p, v);
        double area = 0;
        std::vector<bool> used(cross_pts.size(), false);
        for (int t = 0; t < nt; ++t) {
            const MtTriangle& T = tri[static_cast<std::size_t>(t)];
            const Vec3 n = cross(T[1] - T[0], T[2] - T[0]);
            area += 0.5 * norm(n);
            // towards decreasing values, VTK's convention (a vertex exactly at iso may collapse a
            // triangle to a point)
            if (norm(n) > 1e-12) CHECK(dot(n, g) < 0);
            const Vec3 c = (T[0] + T[1] + T[2]) * (1.0 / 3);
            CHECK(interp(p, v, c) == Approx(iso).margin(1e-9));
            for (const Vec3& x : T) {
                bool found = false;
                for (std::size_t q = 0; q < cross_pts.size(); ++q)
                    if (norm(x - cross_pts[q]) < 1e-9) {
                        found = true;
                        used[q] = true;
                    }
                CHECK(found);
            }
        }
        CHECK(std::all_of(used.begin(), used.end(), [](bool b) { return b; }));
        // (with a vertex exactly at iso, crossings coincide: sort around a point that differs from the first)
        std::sort(cross_pts.begin(), cross_pts.end(), [](const Vec3& a, const Vec3& b) { return a.x < b.x; });
        const double truth = norm(cross_pts.back() - cross_pts.front()) > 1e-12 ? polygon_area(cross_pts, g) : 0.0;
        CHECK(area == Approx(truth).epsilon(1e-9).margin(1e-12));
        // the same tetrahedron with two vertices swapped (the other orientation): the same normals' sense
        std::array<Vec3, 4> p2 = p;
        std::array<double, 4> v2 = v;
        std::swap(p2[0], p2[1]);
        std::swap(v2[0], v2[1]);
        std::array<MtTriangle, 2> tri2;
        REQUIRE(marching_tetrahedron(p2, v2, iso, tri2) == nt);
        for (int t = 0; t < nt; ++t) {
            const MtTriangle& T = tri2[static_cast<std::size_t>(t)];
            const Vec3 n = cross(T[1] - T[0], T[2] - T[0]);
            if (norm(n) > 1e-12) CHECK(dot(n, g) < 0);
        }
        ++checked;
    }
    CHECK(checked > 300);
    // a non-finite value: nothing
    std::array<MtTriangle, 2> tri;
    CHECK(marching_tetrahedron({Vec3{0, 0, 0}, Vec3{1, 0, 0}, Vec3{0, 1, 0}, Vec3{0, 0, 1}}, {0.0, 1.0, NAN, 1.0}, 0.5, tri) == 0);
}
