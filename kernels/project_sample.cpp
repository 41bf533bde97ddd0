#include "kernels/project_sample.hpp"

#include <cassert>
#include <cmath>

#include "kernels/errors.hpp"
#include "kernels/exact_projection.hpp"
#include "kernels/newton_projection.hpp"
#include "kernels/trilinear.hpp"

namespace meshless {

const char* to_string(Projection p) {
    switch (p) {
        case Projection::none: return "none";
        case Projection::approx: return "approx";
        case Projection::exact: return "exact";
    }
    return "?";
}

bool project_sample_cell(const SampleRecord& s, double iso, Projection mode, PointRecord& out,
                         ProjectionStats& stats) {
    const Vec3 p{s.pos[0], s.pos[1], s.pos[2]};
    const Vec3 lo{s.cell_lo[0], s.cell_lo[1], s.cell_lo[2]};
    const Vec3 size{s.cell_size[0], s.cell_size[1], s.cell_size[2]};
    if (std::isnan(s.corner[0])) {
        // a paradigm (A) sample (ooc/sample_store.hpp) carries no cell corners
        if (mode == Projection::exact)
            throw FormatError("samples from a paradigm (A) sample store carry no cell corners: --projection exact needs "
                              "them (use approx, or generate the samples from the volume)");
        const Vec3 n = -normalized(Vec3{s.grad[0], s.grad[1], s.grad[2]});  // towards decreasing values
        out = PointRecord{{s.pos[0], s.pos[1], s.pos[2]},
                          {static_cast<float>(n.x), static_cast<float>(n.y), static_cast<float>(n.z)},
                          s.radius,
                          s.value};
        ++stats.output;
        return true;
    }
    double c[8];
    for (int a = 0; a < 8; ++a) c[a] = s.corner[a];

    Vec3 q = p;  // output position, world units
    switch (mode) {
        case Projection::none: break;
        case Projection::approx:
            assert(false && "the approximate projection is handled inline by project_sample");
            break;
        case Projection::exact: {
            const Vec3 pl{(p.x - lo.x) / size.x, (p.y - lo.y) / size.y, (p.z - lo.z) / size.z};
            const ExactResult r = exact_project_cell(c, pl, iso);
            if (r.status != ExactStatus::ok) { ++stats.missed; return false; }
            q = {lo.x + r.local.x * size.x, lo.y + r.local.y * size.y, lo.z + r.local.z * size.z};
            break;
        }
    }
    const ValueGrad vg = trilinear(c, (q.x - lo.x) / size.x, (q.y - lo.y) / size.y, (q.z - lo.z) / size.z);
    Vec3 n = normalized(to_world_gradient(vg.grad, size));
    if (dot(n, n) == 0.0) n = normalized(Vec3{s.grad[0], s.grad[1], s.grad[2]});
    n = -n;  // towards decreasing values (VTK's convention)
    out.pos[0] = static_cast<float>(q.x);
    out.pos[1] = static_cast<float>(q.y);
    out.pos[2] = static_cast<float>(q.z);
    out.normal[0] = static_cast<float>(n.x);
    out.normal[1] = static_cast<float>(n.y);
    out.normal[2] = static_cast<float>(n.z);
    out.radius = s.radius;
    out.value = static_cast<float>(vg.value);
    ++stats.output;
    return true;
}

}  // namespace meshless
