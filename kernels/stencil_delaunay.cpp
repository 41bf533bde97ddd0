// CGAL lives in this file (and triangle_pair_intersections.cpp) only, compiled as its own object
// library: CGAL's -frounding-math stays here.
#include "kernels/stencil_delaunay.hpp"

#include <CGAL/Delaunay_triangulation_3.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_vertex_base_with_info_3.h>

#include <cmath>
#include <exception>
#include <utility>

namespace meshless {

namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Vb = CGAL::Triangulation_vertex_base_with_info_3<std::uint32_t, K>;
using Tds = CGAL::Triangulation_data_structure_3<Vb>;
using Delaunay = CGAL::Delaunay_triangulation_3<K, Tds>;

}  // namespace

DelaunayStatus stencil_delaunay(std::span<const Vec3> pts, std::vector<std::array<std::uint32_t, 4>>& tets, std::string* what) {
    tets.clear();
    if (pts.size() < 4) return DelaunayStatus::too_few;
    for (const Vec3& p : pts)
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
            if (what) *what = "non-finite coordinate";
            return DelaunayStatus::failed;
        }
    try {
        // one by one in input order (callers pass cell-ordered points, so the previous vertex is a
        // good hint): the range insertion's spatial sort shuffles with a random generator, and the
        // cell order (hence the output order) must depend on the input only
        Delaunay dt;
        Delaunay::Vertex_handle hint;
        for (std::size_t i = 0; i < pts.size(); ++i) {
            const std::size_t before = dt.number_of_vertices();
            const auto v = hint == Delaunay::Vertex_handle() ? dt.insert(K::Point_3(pts[i].x, pts[i].y, pts[i].z))
                                                             : dt.insert(K::Point_3(pts[i].x, pts[i].y, pts[i].z), hint);
            if (dt.number_of_vertices() > before) v->info() = static_cast<std::uint32_t>(i);  // a duplicate keeps the first
            hint = v;
        }
        if (dt.number_of_vertices() < 4) return DelaunayStatus::too_few;
        if (dt.dimension() < 3) return DelaunayStatus::flat;
        tets.reserve(dt.number_of_finite_cells());
        for (auto c = dt.finite_cells_begin(); c != dt.finite_cells_end(); ++c)
            tets.push_back({c->vertex(0)->info(), c->vertex(1)->info(), c->vertex(2)->info(), c->vertex(3)->info()});
        return DelaunayStatus::ok;
    } catch (const std::bad_alloc&) {
        throw;
    } catch (const std::exception& e) {
        tets.clear();
        if (what) *what = e.what();
        return DelaunayStatus::failed;
    }
}

}  // namespace meshless
