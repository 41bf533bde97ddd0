#include "kernels/marching_tetrahedra.hpp"

#include <cmath>
#include <utility>

namespace meshless {

namespace {

Vec3 crossing(const Vec3& pa, double va, const Vec3& pb, double vb, double iso) {
    const double d = vb - va;
    double t = d != 0 ? (iso - va) / d : 0.5;
    t = t < 0 ? 0 : (t > 1 ? 1 : t);
    return pa + (pb - pa) * t;
}

/// Winds `t` so that its normal has a non-negative component along `down`.
void orient(MtTriangle& t, const Vec3& down) {
    if (dot(cross(t[1] - t[0], t[2] - t[0]), down) < 0) std::swap(t[1], t[2]);
}

}  // namespace

int marching_tetrahedron(const std::array<Vec3, 4>& p, const std::array<double, 4>& v, double iso, std::array<MtTriangle, 2>& out) {
    for (double x : v)
        if (!std::isfinite(x)) return 0;
    int in[4], out_[4], ni = 0, no = 0;
    for (int i = 0; i < 4; ++i) {
        if (v[static_cast<std::size_t>(i)] >= iso) in[ni++] = i;
        else out_[no++] = i;
    }
    if (ni == 0 || no == 0) return 0;
    // direction of decreasing values (VTK's normal convention): from the inside vertices' centroid
    // to the outside ones'
    Vec3 ci{0, 0, 0}, co{0, 0, 0};
    for (int i = 0; i < ni; ++i) ci += p[static_cast<std::size_t>(in[i])];
    for (int i = 0; i < no; ++i) co += p[static_cast<std::size_t>(out_[i])];
    const Vec3 down = co * (1.0 / no) - ci * (1.0 / ni);
    auto x = [&](int a, int b) {
        return crossing(p[static_cast<std::size_t>(a)], v[static_cast<std::size_t>(a)], p[static_cast<std::size_t>(b)],
                        v[static_cast<std::size_t>(b)], iso);
    };
    if (ni == 1 || no == 1) {
        const int apex = ni == 1 ? in[0] : out_[0];
        const int* rest = ni == 1 ? out_ : in;
        out[0] = {x(apex, rest[0]), x(apex, rest[1]), x(apex, rest[2])};
        orient(out[0], down);
        return 1;
    }
    // two and two: the quadrilateral in0-out0, in0-out1, in1-out1, in1-out0 (a cycle)
    const Vec3 q0 = x(in[0], out_[0]), q1 = x(in[0], out_[1]), q2 = x(in[1], out_[1]), q3 = x(in[1], out_[0]);
    const Vec3 d02 = q2 - q0, d13 = q3 - q1;
    if (dot(d02, d02) <= dot(d13, d13)) {
        out[0] = {q0, q1, q2};
        out[1] = {q0, q2, q3};
    } else {
        out[0] = {q1, q2, q3};
        out[1] = {q1, q3, q0};
    }
    orient(out[0], down);
    orient(out[1], down);
    return 2;
}

}  // namespace meshless
