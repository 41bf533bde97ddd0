// Triangle rasterizer (see triangle_rasterizer.hpp).
#include "kernels/triangle_rasterizer.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "kernels/shading.hpp"

namespace meshless {

namespace {

constexpr int kSubBits = 8;                 // 1/256 pixel
constexpr long long kSub = 1LL << kSubBits;
constexpr double kMaxOffsetPx = 2097152.0;  // 2^21: edge products stay below 2^61

struct ScreenVertex {
    long long X = 0, Y = 0;  // screen position, 1/256 pixel
    double depth = 0;
    Vec3 cam;                // camera-space position
    bool ok = false;
};

/// Edge function of edge a -> b at p (twice the signed area of a, b, p in 1/256-pixel units).
long long edge(const ScreenVertex& a, const ScreenVertex& b, long long px, long long py) {
    return (b.X - a.X) * (py - a.Y) - (b.Y - a.Y) * (px - a.X);
}

/// Top-left rule for a triangle with a positive edge(a, b, c): the edge a -> b is a left edge when
/// it goes up the screen (y down), a top edge when horizontal going right.
bool owns_edge(const ScreenVertex& a, const ScreenVertex& b) {
    const long long dy = b.Y - a.Y, dx = b.X - a.X;
    return dy < 0 || (dy == 0 && dx > 0);
}

long long floor_div(long long a, long long b) { return a >= 0 ? a / b : -((-a + b - 1) / b); }

}  // namespace

std::array<Vec3, 2> mesh_bounds(const Mesh& mesh) {
    constexpr double inf = std::numeric_limits<double>::infinity();
    double lo[3] = {inf, inf, inf}, hi[3] = {-inf, -inf, -inf};
    bool any = false;
    for (std::size_t v = 0; v + 2 < mesh.xyz.size(); v += 3) {
        const float* p = &mesh.xyz[v];
        if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])) continue;
        any = true;
        for (int k = 0; k < 3; ++k) {
            lo[k] = std::min(lo[k], double(p[k]));
            hi[k] = std::max(hi[k], double(p[k]));
        }
    }
    if (!any) return {Vec3{0, 0, 0}, Vec3{0, 0, 0}};
    return {Vec3{lo[0], lo[1], lo[2]}, Vec3{hi[0], hi[1], hi[2]}};
}

Image render_triangles(const Mesh& mesh, const Camera& cam, const ShadingParams& shading_in,
                       const std::array<Vec3, 2>& bounds, TriangleStats* stats, std::vector<std::uint32_t>* coverage) {
    ShadingParams shading = shading_in;
    if (shading.color_by == ColorBy::value) shading.color_by = ColorBy::none;  // a mesh carries no values
    const ViewTransform view = make_view(cam, bounds[0], bounds[1]);
    const detail::Shader shader(shading);
    const int W = view.width, H = view.height;
    const std::size_t npix = static_cast<std::size_t>(W) * static_cast<std::size_t>(H);

    Image img;
    img.width = W;
    img.height = H;
    img.rgb.resize(3 * npix);
    for (std::size_t i = 0; i < npix; ++i)
        for (int k = 0; k < 3; ++k) img.rgb[3 * i + static_cast<std::size_t>(k)] = shading.background[static_cast<std::size_t>(k)];
    std::vector<float> zbuf(npix, std::numeric_limits<float>::infinity());
    if (coverage) coverage->assign(npix, 0);
    TriangleStats st;

    // Project every vertex once.
    const std::size_t nv = mesh.vertex_count();
    const bool has_normals = mesh.normals.size() == mesh.xyz.size();
    std::vector<ScreenVertex> sv(nv);
    for (std::size_t v = 0; v < nv; ++v) {
        const float* p = &mesh.xyz[3 * v];
        if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])) continue;
        const Vec3 w{p[0], p[1], p[2]};
        double sx = 0, sy = 0, depth = 0;
        if (!view.project(w, sx, sy, depth)) continue;
        if (!(std::abs(sx - view.cx) < kMaxOffsetPx) || !(std::abs(sy - view.cy) < kMaxOffsetPx)) continue;
        ScreenVertex& s = sv[v];
        s.X = std::llround(sx * kSub);
        s.Y = std::llround(sy * kSub);
        s.depth = depth;
        s.cam = view.to_camera(w);
        s.ok = true;
    }
    const std::span<const std::uint32_t> blocks(mesh.block);
    const long long half = kSub / 2;

    for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
        std::uint32_t id[3] = {mesh.tri[3 * t], mesh.tri[3 * t + 1], mesh.tri[3 * t + 2]};
        if (id[0] >= nv || id[1] >= nv || id[2] >= nv) continue;
        if (!sv[id[0]].ok || !sv[id[1]].ok || !sv[id[2]].ok) continue;
        long long area = edge(sv[id[0]], sv[id[1]], sv[id[2]].X, sv[id[2]].Y);
        if (area == 0) continue;
        if (area < 0) {
            std::swap(id[1], id[2]);
            area = -area;
        }
        const ScreenVertex& a = sv[id[0]];
        const ScreenVertex& b = sv[id[1]];
        const ScreenVertex& c = sv[id[2]];
        const long long minX = std::min({a.X, b.X, c.X}), maxX = std::max({a.X, b.X, c.X});
        const long long minY = std::min({a.Y, b.Y, c.Y}), maxY = std::max({a.Y, b.Y, c.Y});
        // pixels whose centres i * 256 + 128 lie in [min, max]
        const long long i0 = std::max(0LL, floor_div(minX - half + kSub - 1, kSub));
        const long long i1 = std::min(static_cast<long long>(W) - 1, floor_div(maxX - half, kSub));
        const long long j0 = std::max(0LL, floor_div(minY - half + kSub - 1, kSub));
        const long long j1 = std::min(static_cast<long long>(H) - 1, floor_div(maxY - half, kSub));
        if (i0 > i1 || j0 > j1) continue;
        ++st.triangles_drawn;
        // bias: a fragment exactly on an edge that the triangle does not own is outside
        const long long bias0 = owns_edge(b, c) ? 0 : 1, bias1 = owns_edge(c, a) ? 0 : 1, bias2 = owns_edge(a, b) ? 0 : 1;

        // per-vertex attributes in the (possibly swapped) order a, b, c
        Vec3 nrm[3];
        if (has_normals) {
            for (int k = 0; k < 3; ++k) {
                const float* n = &mesh.normals[3 * std::size_t{id[k]}];
                nrm[k] = Vec3{n[0], n[1], n[2]};
            }
        } else {
            // geometric normal in the mesh's own winding (tri order, not the swapped one)
            const float* p0 = &mesh.xyz[3 * std::size_t{mesh.tri[3 * t]}];
            const float* p1 = &mesh.xyz[3 * std::size_t{mesh.tri[3 * t + 1]}];
            const float* p2 = &mesh.xyz[3 * std::size_t{mesh.tri[3 * t + 2]}];
            const Vec3 g = cross(Vec3{p1[0] - double(p0[0]), p1[1] - double(p0[1]), p1[2] - double(p0[2])},
                                 Vec3{p2[0] - double(p0[0]), p2[1] - double(p0[1]), p2[2] - double(p0[2])});
            nrm[0] = nrm[1] = nrm[2] = g;
        }
        const double inv_area = 1.0 / static_cast<double>(area);
        const ScreenVertex* vx[3] = {&a, &b, &c};

        for (long long j = j0; j <= j1; ++j) {
            const long long py = j * kSub + half;
            for (long long i = i0; i <= i1; ++i) {
                const long long px = i * kSub + half;
                const long long w0 = edge(b, c, px, py), w1 = edge(c, a, px, py), w2 = edge(a, b, px, py);
                if (w0 - bias0 < 0 || w1 - bias1 < 0 || w2 - bias2 < 0) continue;
                const std::size_t pix = static_cast<std::size_t>(j) * static_cast<std::size_t>(W) + static_cast<std::size_t>(i);
                ++st.fragments;
                if (coverage) ++(*coverage)[pix];
                double l[3] = {static_cast<double>(w0) * inv_area, static_cast<double>(w1) * inv_area,
                               static_cast<double>(w2) * inv_area};
                double depth;
                if (view.perspective) {
                    double s = 0;
                    for (int k = 0; k < 3; ++k) {
                        l[k] /= vx[k]->depth;
                        s += l[k];
                    }
                    for (int k = 0; k < 3; ++k) l[k] /= s;
                    depth = 1.0 / s;
                } else {
                    depth = l[0] * a.depth + l[1] * b.depth + l[2] * c.depth;
                }
                const float dz = static_cast<float>(depth);
                if (!(dz < zbuf[pix])) continue;
                zbuf[pix] = dz;

                const Vec3 nw = nrm[0] * l[0] + nrm[1] * l[1] + nrm[2] * l[2];
                const Vec3 pc = a.cam * l[0] + b.cam * l[1] + c.cam * l[2];
                Vec3 vv = view.perspective ? normalized(Vec3{-pc.x, -pc.y, depth}) : Vec3{0, 0, 1};
                Vec3 nc = view.rotate(nw);
                const double len = norm(nc);
                if (!(len > 1e-30) || !std::isfinite(len)) {
                    nc = vv;
                } else {
                    nc = nc * (1.0 / len);
                    if (shading.two_sided && dot(nc, vv) < 0) nc = nc * -1.0;
                }
                PointRecord rec{};
                rec.normal[0] = static_cast<float>(nw.x);
                rec.normal[1] = static_cast<float>(nw.y);
                rec.normal[2] = static_cast<float>(nw.z);
                const std::uint32_t base = splat_base_color(shading, rec, blocks, t);
                const float colour[3] = {float((base >> 16) & 0xff) / 255.0f, float((base >> 8) & 0xff) / 255.0f,
                                         float(base & 0xff) / 255.0f};
                const std::uint32_t rgb = shader.shade(colour, float(nc.x), float(nc.y), float(nc.z), float(vv.x),
                                                       float(vv.y), float(vv.z));
                detail::unpack_rgb(rgb, &img.rgb[3 * pix]);
            }
        }
    }
    if (stats) *stats = st;
    return img;
}

}  // namespace meshless
