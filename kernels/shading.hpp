// Per-fragment Lambert + Phong shading shared by the splat kernels (dissertation section 3.6).
// Internal to the splat rasterizer. All vectors in camera space (x right, y up, z towards the
// viewer), unit length. Result: packed 0xRRGGBB. Pure, reentrant.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "kernels/splat_rasterizer.hpp"

namespace meshless::detail {

struct Shader {
    float base[3];
    float ambient, diffuse, specular, shininess;
    float light[3];
    int int_shininess = -1;  // >= 0: shininess is this integer, raised by repeated squaring (no powf)

    explicit Shader(const ShadingParams& p) {
        for (int i = 0; i < 3; ++i) base[i] = p.base[i] / 255.0f;
        ambient = static_cast<float>(p.ambient);
        diffuse = static_cast<float>(p.diffuse);
        specular = static_cast<float>(p.specular);
        shininess = static_cast<float>(p.shininess);
        const Vec3 l = normalized(p.light_dir);
        light[0] = static_cast<float>(l.x);
        light[1] = static_cast<float>(l.y);
        light[2] = static_cast<float>(l.z);
        if (p.shininess >= 0 && p.shininess <= 1024 && p.shininess == std::floor(p.shininess))
            int_shininess = static_cast<int>(p.shininess);
    }

    float specular_power(float x) const {
        if (int_shininess < 0) return std::pow(x, shininess);
        float r = 1.0f, b = x;
        for (int e = int_shininess; e; e >>= 1, b *= b)
            if (e & 1) r *= b;
        return r;
    }

    /// n: unit normal (already flipped towards the viewer when two-sided); v: unit vector to the eye.
    std::uint32_t shade(float nx, float ny, float nz, float vx, float vy, float vz) const {
        return shade(base, nx, ny, nz, vx, vy, vz);
    }
    /// As shade() with another surface colour (components in [0, 1]).
    std::uint32_t shade(const float* colour, float nx, float ny, float nz, float vx, float vy, float vz) const {
        const float ndl = nx * light[0] + ny * light[1] + nz * light[2];
        float lum = ambient;
        float spec = 0.0f;
        if (ndl > 0.0f) {
            lum += diffuse * ndl;
            if (specular > 0.0f) {
                // Phong: reflect the light about the normal, compare with the view vector.
                const float rx = 2 * ndl * nx - light[0], ry = 2 * ndl * ny - light[1], rz = 2 * ndl * nz - light[2];
                const float rdv = rx * vx + ry * vy + rz * vz;
                if (rdv > 0.0f) spec = specular * specular_power(rdv);
            }
        }
        std::uint32_t out = 0;
        for (int i = 0; i < 3; ++i) {
            const float c = std::clamp(colour[i] * lum + spec, 0.0f, 1.0f);
            out = (out << 8) | static_cast<std::uint32_t>(c * 255.0f + 0.5f);
        }
        return out;
    }
};

inline void unpack_rgb(std::uint32_t c, std::uint8_t* dst) {
    dst[0] = static_cast<std::uint8_t>(c >> 16);
    dst[1] = static_cast<std::uint8_t>(c >> 8);
    dst[2] = static_cast<std::uint8_t>(c);
}

/// Rotation of a world-space point or direction into camera space, in float.
struct FloatView {
    float r[3][3];
    float c[3];
    float distance, focal, near_depth, cx, cy;
    bool perspective;
    explicit FloatView(const ViewTransform& v) {
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) r[i][j] = v.rot[i][j];
        c[0] = static_cast<float>(v.centre.x);
        c[1] = static_cast<float>(v.centre.y);
        c[2] = static_cast<float>(v.centre.z);
        distance = static_cast<float>(v.distance);
        focal = static_cast<float>(v.focal_px);
        near_depth = static_cast<float>(v.near_depth);
        cx = static_cast<float>(v.cx);
        cy = static_cast<float>(v.cy);
        perspective = v.perspective;
    }
    void rotate(const float* d, float* out) const {
        for (int i = 0; i < 3; ++i) out[i] = r[i][0] * d[0] + r[i][1] * d[1] + r[i][2] * d[2];
    }
    void point(const float* p, float* out) const {
        const float d[3] = {p[0] - c[0], p[1] - c[1], p[2] - c[2]};
        rotate(d, out);
    }
};

/// Unit camera-space normal of a record facing the viewer (two-sided) and the unit view vector
/// from the camera-space point pc (depth = distance - pc.z) to the eye.
inline void oriented_normal(const FloatView& fv, const PointRecord& rec, const float* pc, float depth,
                            bool two_sided, float* n, float* v) {
    if (fv.perspective) {
        const float inv = 1.0f / std::sqrt(pc[0] * pc[0] + pc[1] * pc[1] + depth * depth);
        v[0] = -pc[0] * inv;
        v[1] = -pc[1] * inv;
        v[2] = depth * inv;
    } else {
        v[0] = 0;
        v[1] = 0;
        v[2] = 1;
    }
    fv.rotate(rec.normal, n);
    const float len2 = n[0] * n[0] + n[1] * n[1] + n[2] * n[2];
    if (!(len2 > 1e-20f) || !std::isfinite(len2)) {
        n[0] = v[0];
        n[1] = v[1];
        n[2] = v[2];
        return;
    }
    float inv = 1.0f / std::sqrt(len2);
    if (two_sided && n[0] * v[0] + n[1] * v[1] + n[2] * v[2] < 0) inv = -inv;
    n[0] *= inv;
    n[1] *= inv;
    n[2] *= inv;
}

}  // namespace meshless::detail
