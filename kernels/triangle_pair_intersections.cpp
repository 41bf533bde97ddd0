// CGAL lives in this file only (compiled as its own object library: CGAL's -frounding-math stays here).
#include "kernels/triangle_pair_intersections.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/box_intersection_d.h>

#include <stdexcept>
#include <string>
#include <vector>

namespace meshless {

namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = K::Point_3;
using Triangle = K::Triangle_3;
using Segment = K::Segment_3;
using Box = CGAL::Box_intersection_d::Box_with_info_d<double, 3, std::size_t>;

struct Soup {
    std::span<const double> xyz;
    std::span<const std::uint32_t> tri, group;
    std::vector<std::uint8_t> skip;  // degenerate

    Point point(std::uint32_t v) const { return {xyz[3 * v], xyz[3 * v + 1], xyz[3 * v + 2]}; }
    Triangle triangle(std::size_t t) const { return {point(tri[3 * t]), point(tri[3 * t + 1]), point(tri[3 * t + 2])}; }

    Soup(std::span<const double> x, std::span<const std::uint32_t> t, std::span<const std::uint32_t> g)
        : xyz(x), tri(t), group(g) {
        if (xyz.size() % 3 || tri.size() % 3) throw std::invalid_argument("triangle pairs: arrays are not multiples of 3");
        const std::size_t nt = tri.size() / 3, nv = xyz.size() / 3;
        if (group.size() != nt)
            throw std::invalid_argument("triangle pairs: " + std::to_string(group.size()) + " group ids for " +
                                        std::to_string(nt) + " triangles");
        for (std::uint32_t v : tri)
            if (v >= nv) throw std::invalid_argument("triangle pairs: vertex index " + std::to_string(v) + " out of range");
        skip.resize(nt);
        for (std::size_t i = 0; i < nt; ++i)
            skip[i] = CGAL::collinear(point(tri[3 * i]), point(tri[3 * i + 1]), point(tri[3 * i + 2])) ? 1 : 0;
    }

    /// Classifies a pair of non-degenerate triangles of different groups: 0 none, 1 intersecting, 2 duplicate.
    int classify(std::size_t a, std::size_t b) const {
        const std::uint32_t* A = &tri[3 * a];
        const std::uint32_t* B = &tri[3 * b];
        int shared = 0, ia[3];  // ia: positions in A of the shared vertices
        bool a_shared[3] = {false, false, false}, b_shared[3] = {false, false, false};
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j)
                if (A[i] == B[j] && !a_shared[i] && !b_shared[j]) {
                    a_shared[i] = b_shared[j] = true;
                    ia[shared] = i;
                    ++shared;
                }
        if (shared == 3) return 2;
        if (shared == 2) {
            const Point p = point(A[ia[0]]), q = point(A[ia[1]]);
            int ra = 0, rb = 0;
            while (a_shared[ra]) ++ra;
            while (b_shared[rb]) ++rb;
            const Point r = point(A[ra]), s = point(B[rb]);
            if (!CGAL::coplanar(p, q, r, s)) return 0;
            return CGAL::coplanar_orientation(p, q, r, s) == CGAL::POSITIVE ? 1 : 0;
        }
        if (shared == 1) {
            int j = 0;
            while (!b_shared[j]) ++j;
            const int i = ia[0];
            const Segment opp_a(point(A[(i + 1) % 3]), point(A[(i + 2) % 3]));
            const Segment opp_b(point(B[(j + 1) % 3]), point(B[(j + 2) % 3]));
            return (CGAL::do_intersect(opp_a, triangle(b)) || CGAL::do_intersect(opp_b, triangle(a))) ? 1 : 0;
        }
        return CGAL::do_intersect(triangle(a), triangle(b)) ? 1 : 0;
    }

    void tally(std::size_t a, std::size_t b, TrianglePairStats& st) const {
        ++st.candidates;
        const int c = classify(a, b);
        if (c == 1) ++st.intersecting;
        else if (c == 2) ++st.duplicates;
    }

    std::int64_t degenerate() const {
        std::int64_t n = 0;
        for (auto s : skip) n += s;
        return n;
    }
};

}  // namespace

TrianglePairStats count_intersecting_triangle_pairs(std::span<const double> xyz, std::span<const std::uint32_t> tri,
                                                    std::span<const std::uint32_t> group) {
    const Soup soup(xyz, tri, group);
    TrianglePairStats st;
    st.degenerate = soup.degenerate();
    std::vector<Box> boxes;
    boxes.reserve(group.size());
    for (std::size_t t = 0; t < group.size(); ++t)
        if (!soup.skip[t]) boxes.emplace_back(soup.triangle(t).bbox(), t);
    CGAL::box_self_intersection_d(boxes.begin(), boxes.end(), [&](const Box& a, const Box& b) {
        if (group[a.info()] != group[b.info()]) soup.tally(a.info(), b.info(), st);
    });
    return st;
}

TrianglePairStats count_intersecting_triangle_pairs_brute_force(std::span<const double> xyz,
                                                                std::span<const std::uint32_t> tri,
                                                                std::span<const std::uint32_t> group) {
    const Soup soup(xyz, tri, group);
    TrianglePairStats st;
    st.degenerate = soup.degenerate();
    const std::size_t n = group.size();
    for (std::size_t a = 0; a < n; ++a)
        for (std::size_t b = a + 1; b < n; ++b)
            if (!soup.skip[a] && !soup.skip[b] && group[a] != group[b]) soup.tally(a, b, st);
    return st;
}

}  // namespace meshless
