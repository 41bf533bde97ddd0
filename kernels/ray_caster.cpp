#include "kernels/ray_caster.hpp"

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <mutex>

#include "kernels/errors.hpp"

namespace meshless {

namespace {

constexpr int kTableSize = 4096;
constexpr int kMaxBatch = 128;
constexpr double kMaxSamplesPerRay = double(1 << 26);

/// The transfer function tabulated over its control range: colour, opacity per ref_step, and the
/// opacity corrected for a full step.
struct TfTable {
    double lo = 0, scale = 0;  // index = (v - lo) * scale
    std::vector<std::array<float, 5>> e;  // r, g, b, a, a'
    explicit TfTable(const TransferFunction& tf, double ratio) {
        lo = tf.lo();
        const double span = tf.hi() - tf.lo();
        scale = span > 0 ? (kTableSize - 1) / span : 0;
        e.resize(kTableSize);
        for (int i = 0; i < kTableSize; ++i) {
            // a single point (span 0): the whole table is that point (clamping does the rest below)
            const double v = span > 0 ? lo + i / scale : lo;
            const auto c = tf.at(v);
            const double a_corr = c[3] >= 1.0 ? 1.0 : 1.0 - std::pow(1.0 - c[3], ratio);
            e[i] = {static_cast<float>(c[0]), static_cast<float>(c[1]), static_cast<float>(c[2]), static_cast<float>(c[3]),
                    static_cast<float>(a_corr)};
        }
        // values below the first control point take it as it is, also across a step at lo
        if (span > 0 && tf.points().size() > 1 && tf.points()[1].value == lo) below = tf.at(std::nextafter(lo, -INFINITY));
        else below = tf.at(lo);
        below_corr = below[3] >= 1.0 ? 1.0 : 1.0 - std::pow(1.0 - below[3], ratio);
    }
    std::array<double, 4> below{};
    double below_corr = 0;

    /// r, g, b, a (per ref_step), a' (per step) at v. NaN: transparent.
    void lookup(double v, float out[5]) const {
        if (!(v == v)) {
            for (int i = 0; i < 5; ++i) out[i] = 0;
            return;
        }
        const double x = (v - lo) * scale;
        if (v < lo) {
            for (int i = 0; i < 4; ++i) out[i] = static_cast<float>(below[i]);
            out[4] = static_cast<float>(below_corr);
            return;
        }
        if (!(x < kTableSize - 1)) {
            for (int i = 0; i < 5; ++i) out[i] = e[kTableSize - 1][i];
            return;
        }
        const int i = static_cast<int>(x);
        const float f = static_cast<float>(x - i);
        const auto& a = e[i];
        const auto& b = e[i + 1];
        for (int k = 0; k < 5; ++k) out[k] = a[k] + f * (b[k] - a[k]);
    }
};

struct Ray {
    Vec3 o, d;
};

Ray pixel_ray(const ViewTransform& v, double sx, double sy) {
    // camera space: x right, y up, z towards the viewer; eye at (0, 0, distance)
    const double x = (sx - v.cx) / v.focal_px, y = -(sy - v.cy) / v.focal_px;
    Vec3 oc, dc;
    if (v.perspective) {
        oc = {0, 0, v.distance};
        dc = normalized(Vec3{x, y, -1});
    } else {
        oc = {x, y, v.distance};
        dc = {0, 0, -1};
    }
    // world = centre + R^T c (R's rows are the camera axes in world space)
    auto to_world = [&](const Vec3& c) {
        return Vec3{v.rot[0][0] * c.x + v.rot[1][0] * c.y + v.rot[2][0] * c.z,
                    v.rot[0][1] * c.x + v.rot[1][1] * c.y + v.rot[2][1] * c.z,
                    v.rot[0][2] * c.x + v.rot[1][2] * c.y + v.rot[2][2] * c.z};
    };
    return {v.centre + to_world(oc), normalized(to_world(dc))};
}

/// Slab intersection of the ray with [lo, hi]; false when it misses (or only touches behind the origin).
bool intersect_box(const Ray& r, const std::array<Vec3, 2>& box, double& t0, double& t1) {
    t0 = 0;
    t1 = std::numeric_limits<double>::infinity();
    for (int a = 0; a < 3; ++a) {
        if (r.d[a] == 0) {
            if (r.o[a] < box[0][a] || r.o[a] > box[1][a]) return false;
            continue;
        }
        const double inv = 1.0 / r.d[a];
        double ta = (box[0][a] - r.o[a]) * inv, tb = (box[1][a] - r.o[a]) * inv;
        if (ta > tb) std::swap(ta, tb);
        t0 = std::max(t0, ta);
        t1 = std::min(t1, tb);
    }
    return t0 < t1;
}

struct TileScratch {
    std::vector<Vec3> pos, grad;
    std::vector<double> val, len;
    std::vector<std::array<float, 5>> lut;  // the transfer function's entry of each sample
    std::vector<int> lit;                   // central differences: the samples that reach the pixel
    std::vector<Vec3> fd_pos;               // ... and their six neighbours
    std::vector<double> fd_val;
    TileScratch()
        : pos(kMaxBatch), grad(kMaxBatch), val(kMaxBatch), len(kMaxBatch), lut(kMaxBatch), lit(kMaxBatch),
          fd_pos(6 * kMaxBatch), fd_val(6 * kMaxBatch) {}
};

/// Where a ray stands between the parts of a picture (RayCastParts), and the whole of it for
/// ray_cast_rgba: its sample count (0: it misses the box), the next sample, the premultiplied colour
/// and opacity so far, the exit of the empty-space cell it is in, its batch size, its way along z.
struct RayState {
    std::int64_t n = 0, k = 0;
    double C[3] = {0, 0, 0}, A = 0;
    double cell_end = -std::numeric_limits<double>::infinity();
    int batch = 8;
    bool rising = true;  // its z rises or stays
};

/// The samples a march takes: midpoint z in [lo, hi), or [lo, hi] when closed.
struct ZRange {
    double lo = -std::numeric_limits<double>::infinity(), hi = std::numeric_limits<double>::infinity();
    bool closed = true;
    bool holds(double z) const { return z >= lo && (z < hi || (closed && z == hi)); }
};

class Caster {
public:
    Caster(const std::array<Vec3, 2>& box, const ViewTransform& view, const TransferFunction& tf, const RayCastParams& p,
           const ValueBoundsGrid* skip)
        : box_(box), view_(view), p_(p), table_(tf, p.step / p.ref_step), skip_(skip),
          fd_(p.shade && p.gradient_step[0] > 0 && p.gradient_step[1] > 0 && p.gradient_step[2] > 0) {
        if (p.shininess >= 0 && p.shininess <= 1024 && p.shininess == std::floor(p.shininess))
            int_shininess_ = static_cast<int>(p.shininess);
        if (skip_) {
            transparent_.resize(static_cast<std::size_t>(skip_->count()));
            for (std::size_t c = 0; c < transparent_.size(); ++c)
                transparent_[c] = tf.max_opacity(skip_->vmin[c], skip_->vmax[c]) <= 0.0;
        }
    }

    /// Starts the ray through pixel centre (sx, sy): its sample count (0: it misses the box) and way.
    void begin(double sx, double sy, RayState& rs, RayCastStats& st) const {
        ++st.rays;
        const Ray r = pixel_ray(view_, sx, sy);
        double t0, t1;
        if (!intersect_box(r, box_, t0, t1)) return;
        ++st.rays_hit;
        const double nsteps = std::ceil((t1 - t0) / p_.step);
        if (!(nsteps <= kMaxSamplesPerRay))
            throw InvalidArgument("ray caster: a ray of more than 2^26 samples (step " + std::to_string(p_.step) + " too small)");
        rs.n = static_cast<std::int64_t>(nsteps);
        rs.rising = r.d.z >= 0;
    }

    /// Marches the ray through pixel centre (sx, sy) on from its state, through its samples whose
    /// midpoint z lies in `zr`, evaluating `field`; stops at the first sample beyond (or at the end).
    void march(const Field& field, double sx, double sy, RayState& rs, const ZRange& zr, TileScratch& s, RayCastStats& st) const {
        if (rs.k >= rs.n) return;
        const Ray r = pixel_ray(view_, sx, sy);
        double t0, t1;
        intersect_box(r, box_, t0, t1);  // (the same t0, t1 as begin's)
        const double step = p_.step;
        const std::int64_t n = rs.n;
        std::int64_t k = rs.k;
        double* C = rs.C;
        double A = rs.A;
        const bool shade = p_.shade;
        // The macro cell the samples are in, and where the ray leaves it: cells are looked up only
        // when a sample passes that exit (a few times per cell, not once per sample).
        double& cell_end = rs.cell_end;
        bool beyond = false;  // the next sample lies beyond zr
        while (k < n && !beyond) {
            int m = 0;
            while (m < rs.batch && k < n) {
                const double tk = t0 + static_cast<double>(k) * step;
                const double len = std::min(step, t1 - tk);
                const double tm = tk + 0.5 * len;
                const Vec3 pos = r.o + r.d * tm;
                if (!zr.holds(pos.z)) {
                    beyond = true;
                    break;
                }
                if (skip_ && tm >= cell_end) {
                    const std::int64_t c = cell_of(pos);
                    cell_end = cell_exit(r, c);
                    if (transparent_[static_cast<std::size_t>(c)]) {
                        // the first sample whose midpoint lies beyond the cell's exit
                        const double next = std::ceil((cell_end - t0) / step - 0.5);
                        const std::int64_t k2 = std::max<std::int64_t>(k + 1, next < static_cast<double>(n) ? static_cast<std::int64_t>(next) : n);
                        st.skipped += static_cast<std::uint64_t>(k2 - k);
                        k = k2;
                        continue;
                    }
                }
                s.pos[m] = pos;
                s.len[m] = len;
                ++m;
                ++k;
            }
            if (m == 0) break;
            field.evaluate(std::span<const Vec3>(s.pos.data(), m), std::span<double>(s.val.data(), m),
                           shade && !fd_ ? std::span<Vec3>(s.grad.data(), m) : std::span<Vec3>());
            st.samples += static_cast<std::uint64_t>(m);
            for (int i = 0; i < m; ++i) table_.lookup(s.val[i], s.lut[static_cast<std::size_t>(i)].data());
            if (fd_) central_differences(field, s, m, A);
            for (int i = 0; i < m; ++i) {
                const float* e = s.lut[static_cast<std::size_t>(i)].data();
                if (e[3] <= 0.0f) continue;
                const double a = opacity(e, s.len[i]);
                double c[3] = {e[0], e[1], e[2]};
                if (shade) shade_colour(s.grad[i], r.d, c);
                const double w = (1.0 - A) * a;
                C[0] += w * c[0];
                C[1] += w * c[1];
                C[2] += w * c[2];
                A += w;
                if (A >= p_.termination) {
                    ++st.terminated;
                    k = n;
                    break;
                }
            }
            rs.batch = std::min(2 * rs.batch, kMaxBatch);
        }
        rs.k = k;
        rs.A = A;
    }

private:
    /// The opacity of a sample of entry e over a segment of length len (the step's, or corrected).
    double opacity(const float* e, double len) const {
        if (len == p_.step) return e[4];
        return e[3] >= 1.0f ? 1.0 : 1.0 - std::pow(1.0 - static_cast<double>(e[3]), len / p_.ref_step);
    }

    /// s.grad of the samples of this batch that reach the pixel (opacity > 0, up to where the
    /// accumulated opacity, starting from A, reaches the termination: the compositing's own
    /// arithmetic, so exactly the samples it shades), by central differences of the field's values.
    void central_differences(const Field& field, TileScratch& s, int m, double A) const {
        int nl = 0;
        for (int i = 0; i < m; ++i) {
            const float* e = s.lut[static_cast<std::size_t>(i)].data();
            if (e[3] <= 0.0f) continue;
            s.lit[static_cast<std::size_t>(nl++)] = i;
            A += (1.0 - A) * opacity(e, s.len[i]);
            if (A >= p_.termination) break;
        }
        const auto& h = p_.gradient_step;
        for (int q = 0; q < nl; ++q) {
            const Vec3& c = s.pos[static_cast<std::size_t>(s.lit[static_cast<std::size_t>(q)])];
            Vec3* o = s.fd_pos.data() + 6 * q;
            o[0] = {c.x + h[0], c.y, c.z};
            o[1] = {c.x - h[0], c.y, c.z};
            o[2] = {c.x, c.y + h[1], c.z};
            o[3] = {c.x, c.y - h[1], c.z};
            o[4] = {c.x, c.y, c.z + h[2]};
            o[5] = {c.x, c.y, c.z - h[2]};
        }
        if (nl == 0) return;
        const std::size_t n6 = 6 * static_cast<std::size_t>(nl);
        field.evaluate(std::span<const Vec3>(s.fd_pos.data(), n6), std::span<double>(s.fd_val.data(), n6), {});
        for (int q = 0; q < nl; ++q) {
            const int i = s.lit[static_cast<std::size_t>(q)];
            const double* v = s.fd_val.data() + 6 * q;
            double g[3];
            for (int a = 0; a < 3; ++a) {
                const double up = v[2 * a], down = v[2 * a + 1], mid = s.val[i];
                if (std::isfinite(up) && std::isfinite(down)) g[a] = (up - down) / (2 * h[a]);
                else if (std::isfinite(up)) g[a] = (up - mid) / h[a];
                else if (std::isfinite(down)) g[a] = (mid - down) / h[a];
                else g[a] = 0;
            }
            s.grad[static_cast<std::size_t>(i)] = {g[0], g[1], g[2]};
        }
    }

    std::int64_t cell_of(const Vec3& p) const {
        std::int64_t ijk[3];
        for (int a = 0; a < 3; ++a) {
            const double u = std::floor((p[a] - skip_->origin[a]) / skip_->cell[a]);
            ijk[a] = u < 0 ? 0 : u >= static_cast<double>(skip_->dims[a]) ? skip_->dims[a] - 1 : static_cast<std::int64_t>(u);
        }
        return skip_->index(ijk[0], ijk[1], ijk[2]);
    }

    /// Ray parameter where the ray leaves macro cell c (the cells at the grid's ends reach to infinity,
    /// as cell_of clamps positions into them).
    double cell_exit(const Ray& r, std::int64_t c) const {
        const std::int64_t ijk[3] = {c % skip_->dims[0], (c / skip_->dims[0]) % skip_->dims[1], c / (skip_->dims[0] * skip_->dims[1])};
        double te = std::numeric_limits<double>::infinity();
        for (int a = 0; a < 3; ++a) {
            if (r.d[a] > 0) {
                if (ijk[a] == skip_->dims[a] - 1) continue;
                te = std::min(te, (skip_->origin[a] + static_cast<double>(ijk[a] + 1) * skip_->cell[a] - r.o[a]) / r.d[a]);
            } else if (r.d[a] < 0) {
                if (ijk[a] == 0) continue;
                te = std::min(te, (skip_->origin[a] + static_cast<double>(ijk[a]) * skip_->cell[a] - r.o[a]) / r.d[a]);
            }
        }
        return te;
    }

    /// x^shininess; an integer exponent by repeated squaring (no pow per sample).
    double power(double x) const {
        if (int_shininess_ < 0) return std::pow(x, p_.shininess);
        double r = 1.0, b = x;
        for (int e = int_shininess_; e; e >>= 1, b *= b)
            if (e & 1) r *= b;
        return r;
    }

    void shade_colour(const Vec3& g, const Vec3& d, double c[3]) const {
        const double gl = norm(g);
        double lum = p_.ambient + p_.diffuse, spec = 0;
        if (gl > 0 && std::isfinite(gl)) {
            const double ndl = std::abs(dot(g, d)) / gl;  // two-sided, light = -d
            lum = p_.ambient + p_.diffuse * ndl;
            spec = p_.specular > 0 ? p_.specular * power(ndl) : 0.0;
        }
        for (int i = 0; i < 3; ++i) c[i] = std::clamp(c[i] * lum + spec, 0.0, 1.0);
    }

    std::array<Vec3, 2> box_;
    ViewTransform view_;
    RayCastParams p_;
    TfTable table_;
    const ValueBoundsGrid* skip_;
    bool fd_;  // shading gradients by central differences (RayCastParams::gradient_step)
    std::vector<char> transparent_;
    int int_shininess_ = -1;
};

/// A ray's premultiplied colour and opacity as the picture keeps them.
void store_pixel(const RayState& rs, float out[4]) {
    out[0] = static_cast<float>(rs.C[0]);
    out[1] = static_cast<float>(rs.C[1]);
    out[2] = static_cast<float>(rs.C[2]);
    out[3] = static_cast<float>(rs.A);
}

}  // namespace

namespace {
/// The parameters' checks of ray_cast_rgba and RayCastParts.
void check_ray_cast_params(const RayCastParams& params, const ValueBoundsGrid* skip) {
    if (!(params.step > 0) || !std::isfinite(params.step)) throw InvalidArgument("ray caster: step must be positive and finite");
    if (!(params.ref_step > 0) || !std::isfinite(params.ref_step))
        throw InvalidArgument("ray caster: reference step must be positive and finite");
    if (!(params.termination > 0 && params.termination <= 1)) throw InvalidArgument("ray caster: termination must lie in (0, 1]");
    if (skip && (skip->count() <= 0 || skip->vmin.size() != static_cast<std::size_t>(skip->count()) ||
                 skip->vmax.size() != skip->vmin.size()))
        throw InvalidArgument("ray caster: value bounds grid does not match its dimensions");
}

/// Runs tile(t) for every tile t of `tiles`, on `threads` threads (a task_arena).
void for_each_tile(int tiles, int threads, const std::function<void(int)>& tile) {
    if (threads <= 1) {
        for (int t = 0; t < tiles; ++t) tile(t);
        return;
    }
    oneapi::tbb::task_arena arena(threads);
    arena.execute([&] {
        oneapi::tbb::parallel_for(oneapi::tbb::blocked_range<int>(0, tiles, 1), [&](const oneapi::tbb::blocked_range<int>& r) {
            for (int t = r.begin(); t != r.end(); ++t) tile(t);
        });
    });
}

void add_stats(RayCastStats& to, const RayCastStats& st) {
    to.rays += st.rays;
    to.rays_hit += st.rays_hit;
    to.samples += st.samples;
    to.skipped += st.skipped;
    to.terminated += st.terminated;
}
}  // namespace

RgbaImage ray_cast_rgba(const Field& field, const std::array<Vec3, 2>& box, const ViewTransform& view,
                        const TransferFunction& tf, const RayCastParams& params, const ValueBoundsGrid* skip, int threads,
                        RayCastStats* stats, const std::function<void(double)>& progress) {
    check_ray_cast_params(params, skip);
    RgbaImage img;
    img.width = view.width;
    img.height = view.height;
    img.rgba.assign(4 * static_cast<std::size_t>(img.width) * static_cast<std::size_t>(img.height), 0.0f);
    const Caster caster(box, view, tf, params, skip);
    const int T = std::max(1, params.tile);
    const int tx = (img.width + T - 1) / T, ty = (img.height + T - 1) / T;
    const int tiles = tx * ty;
    std::mutex mu;  // stats and progress
    RayCastStats total;
    int done = 0;
    auto run_tile = [&](int t) {
        TileScratch s;
        RayCastStats st;
        const int x0 = (t % tx) * T, y0 = (t / tx) * T;
        const int x1 = std::min(img.width, x0 + T), y1 = std::min(img.height, y0 + T);
        for (int y = y0; y < y1; ++y)
            for (int x = x0; x < x1; ++x) {
                RayState rs;
                caster.begin(x + 0.5, y + 0.5, rs, st);
                caster.march(field, x + 0.5, y + 0.5, rs, ZRange{}, s, st);
                store_pixel(rs, &img.rgba[4 * (static_cast<std::size_t>(y) * img.width + x)]);
            }
        std::lock_guard lock(mu);
        add_stats(total, st);
        ++done;
        if (progress) progress(static_cast<double>(done) / tiles);
    };
    for_each_tile(tiles, threads, run_tile);
    if (stats) *stats = total;
    return img;
}

struct RayCastParts::Impl {
    Impl(const std::array<Vec3, 2>& box, const ViewTransform& view, const TransferFunction& tf, const RayCastParams& params,
         const ValueBoundsGrid* skip)
        : caster(box, view, tf, params, skip), width(view.width), height(view.height), tile(std::max(1, params.tile)) {
        rays.resize(static_cast<std::size_t>(width) * static_cast<std::size_t>(height));
        for (int y = 0; y < height; ++y)
            for (int x = 0; x < width; ++x) caster.begin(x + 0.5, y + 0.5, rays[static_cast<std::size_t>(y) * width + x], stats);
    }
    Caster caster;
    int width, height, tile;
    std::vector<RayState> rays;
    RayCastStats stats;
};

RayCastParts::RayCastParts(const std::array<Vec3, 2>& box, const ViewTransform& view, const TransferFunction& tf,
                           const RayCastParams& params, const ValueBoundsGrid* skip) {
    check_ray_cast_params(params, skip);
    impl_ = std::make_unique<Impl>(box, view, tf, params, skip);
}

RayCastParts::~RayCastParts() = default;

bool RayCastParts::pending(bool rising) const {
    return std::any_of(impl_->rays.begin(), impl_->rays.end(), [rising](const RayState& r) { return r.rising == rising && r.k < r.n; });
}

void RayCastParts::advance(const Field& field, bool rising, const std::array<double, 2>& z, bool closed, int threads) {
    Impl& m = *impl_;
    const int T = m.tile;
    const int tx = (m.width + T - 1) / T, ty = (m.height + T - 1) / T;
    const ZRange zr{z[0], z[1], closed};
    std::mutex mu;
    for_each_tile(tx * ty, threads, [&](int t) {
        TileScratch s;
        RayCastStats st;
        const int x0 = (t % tx) * T, y0 = (t / tx) * T;
        const int x1 = std::min(m.width, x0 + T), y1 = std::min(m.height, y0 + T);
        for (int y = y0; y < y1; ++y)
            for (int x = x0; x < x1; ++x) {
                RayState& rs = m.rays[static_cast<std::size_t>(y) * m.width + x];
                if (rs.rising == rising) m.caster.march(field, x + 0.5, y + 0.5, rs, zr, s, st);
            }
        std::lock_guard lock(mu);
        add_stats(m.stats, st);
    });
}

RgbaImage RayCastParts::image() const {
    RgbaImage img;
    img.width = impl_->width;
    img.height = impl_->height;
    img.rgba.resize(4 * impl_->rays.size());
    for (std::size_t i = 0; i < impl_->rays.size(); ++i) store_pixel(impl_->rays[i], &img.rgba[4 * i]);
    return img;
}

const RayCastStats& RayCastParts::stats() const { return impl_->stats; }

Image compose_over_background(const RgbaImage& img, const std::array<double, 3>& bg) {
    Image out;
    out.width = img.width;
    out.height = img.height;
    const std::size_t n = static_cast<std::size_t>(img.width) * static_cast<std::size_t>(img.height);
    out.rgb.resize(3 * n);
    for (std::size_t i = 0; i < n; ++i) {
        const float* p = &img.rgba[4 * i];
        for (int c = 0; c < 3; ++c) {
            const double v = std::clamp(static_cast<double>(p[c]) + (1.0 - static_cast<double>(p[3])) * bg[static_cast<std::size_t>(c)], 0.0, 1.0);
            out.rgb[3 * i + c] = static_cast<std::uint8_t>(std::lround(255.0 * v));
        }
    }
    return out;
}

}  // namespace meshless
