// Ray casting (kernels/ray_caster.hpp) against closed forms: a constant field (A = 1 - (1 - a)^(D /
// ref_step)), a field linear across the image (colour = ramp(x) A), a field linear along the rays
// (the emission-absorption integral, front to back), a thin slab seen obliquely, opacity
// correction (half the step, the same picture), empty-space skipping (no change for a volume; within
// a tolerance for a meshless field), early termination, and the same bytes for any thread count.
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <random>

#include "kernels/block_minmax.hpp"
#include "kernels/errors.hpp"
#include "kernels/image_compare.hpp"
#include "kernels/make_field.hpp"
#include "kernels/merge_near_duplicates.hpp"
#include "kernels/ray_caster.hpp"
#include "kernels/trilinear_field.hpp"

using namespace meshless;

namespace {

/// f(p) = c0 + g . p over the box [lo, hi] (analytic value and gradient).
class LinearField final : public Field {
public:
    LinearField(double c0, Vec3 g, std::array<Vec3, 2> box) : c0_(c0), g_(g), box_(box) {}
    void evaluate(std::span<const Vec3> p, std::span<double> v, std::span<Vec3> grad) const override {
        for (std::size_t i = 0; i < p.size(); ++i) {
            v[i] = c0_ + dot(g_, p[i]);
            if (!grad.empty()) grad[i] = g_;
        }
    }
    std::array<Vec3, 2> bounds() const override { return box_; }
    std::string name() const override { return "linear"; }

private:
    double c0_;
    Vec3 g_;
    std::array<Vec3, 2> box_;
};

/// Orthographic camera looking down -z (azimuth 0, elevation 0: x right, y up).
Camera ortho_front(int w, int h) {
    Camera c;
    c.azimuth_deg = 0;
    c.elevation_deg = 0;
    c.width = w;
    c.height = h;
    c.perspective = false;
    return c;
}

/// World x, y of the centre of pixel (i, j) for ortho_front (camera axes = world axes).
Vec3 pixel_world(const ViewTransform& v, int i, int j) {
    return {v.centre.x + (i + 0.5 - v.cx) / v.focal_px, v.centre.y - (j + 0.5 - v.cy) / v.focal_px, 0};
}

const float* px(const RgbaImage& img, int i, int j) { return &img.rgba[4 * (static_cast<std::size_t>(j) * img.width + i)]; }

/// A smooth blob volume: exp(-4 r^2) on an n^3 grid over [-1, 1]^3, float32.
Volume blob_volume(int n) {
    GridSpec g;
    g.dims = {n, n, n};
    g.origin = {-1, -1, -1};
    g.spacing = {2.0 / (n - 1), 2.0 / (n - 1), 2.0 / (n - 1)};
    Volume v(g, SampleType::f32);
    float* f = reinterpret_cast<float*>(v.bytes.data());
    for (int k = 0; k < n; ++k)
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                const double x = -1 + i * g.spacing[0], y = -1 + j * g.spacing[1], z = -1 + k * g.spacing[2];
                f[g.index(i, j, k)] = static_cast<float>(std::exp(-4 * (x * x + y * y + z * z)) + 0.3 * x);
            }
    return v;
}

/// exp(-4 r^2) + 0.3 x, the function blob_volume samples, with its analytic gradient.
class BlobField final : public Field {
public:
    void evaluate(std::span<const Vec3> p, std::span<double> v, std::span<Vec3> grad) const override {
        for (std::size_t i = 0; i < p.size(); ++i) {
            const Vec3& q = p[i];
            const double e = std::exp(-4 * dot(q, q));
            v[i] = e + 0.3 * q.x;
            if (!grad.empty()) grad[i] = q * (-8 * e) + Vec3{0.3, 0, 0};
        }
    }
    std::array<Vec3, 2> bounds() const override { return {Vec3{-1, -1, -1}, Vec3{1, 1, 1}}; }
    std::string name() const override { return "blob"; }
};

/// The values of one field with the gradients of another (the pictures of two such fields differ
/// in their shading only).
class ValuesWithGradients final : public Field {
public:
    ValuesWithGradients(const Field& values, const Field& gradients) : v_(values), g_(gradients) {}
    void evaluate(std::span<const Vec3> p, std::span<double> v, std::span<Vec3> grad) const override {
        v_.evaluate(p, v, {});
        if (grad.empty()) return;
        std::vector<double> scratch(p.size());
        g_.evaluate(p, scratch, grad);
    }
    std::array<Vec3, 2> bounds() const override { return v_.bounds(); }
    std::string name() const override { return "values+gradients"; }

private:
    const Field& v_;
    const Field& g_;
};

/// RMS difference of two premultiplied images (all four channels).
double rgba_rms(const RgbaImage& a, const RgbaImage& b) {
    double s = 0;
    for (std::size_t i = 0; i < a.rgba.size(); ++i) s += (a.rgba[i] - b.rgba[i]) * (a.rgba[i] - b.rgba[i]);
    return std::sqrt(s / static_cast<double>(a.rgba.size()));
}

}  // namespace

TEST_CASE("ray casting a constant field gives the closed-form opacity 1 - (1 - a)^(D / ref_step)", "[render]") {
    const double D = 0.7, a = 0.2, ref = 0.05;
    const std::array<Vec3, 2> box{Vec3{0, 0, 0}, Vec3{1, 1, D}};
    const LinearField f(0.5, {0, 0, 0}, box);
    const TransferFunction tf({{0.5, 1, 1, 1, a}});
    const ViewTransform view = make_view(ortho_front(64, 64), box[0], box[1]);
    for (double step : {0.05, 0.03, 0.011}) {  // 0.03 and 0.011 leave a shorter last segment
        RayCastParams p;
        p.step = step;
        p.ref_step = ref;
        p.termination = 1.0;
        const RgbaImage img = ray_cast_rgba(f, box, view, tf, p, nullptr, 1);
        const double want = 1 - std::pow(1 - a, D / ref);
        int inside = 0;
        for (int j = 0; j < 64; ++j)
            for (int i = 0; i < 64; ++i) {
                const Vec3 w = pixel_world(view, i, j);
                if (w.x < 0.02 || w.x > 0.98 || w.y < 0.02 || w.y > 0.98) continue;
                ++inside;
                CHECK(px(img, i, j)[3] == Approx(want).margin(2e-6));
                CHECK(px(img, i, j)[0] == Approx(want).margin(2e-6));  // white, premultiplied
            }
        CHECK(inside > 400);
        // rays that miss the box stay empty
        CHECK(px(img, 0, 0)[3] == 0.0f);
    }
}

TEST_CASE("ray casting a field linear across the image gives colour = ramp(x) times the opacity", "[render]") {
    const double D = 0.5, a = 0.3, ref = 0.1;
    const std::array<Vec3, 2> box{Vec3{0, 0, 0}, Vec3{1, 1, D}};
    const LinearField f(0, {1, 0, 0}, box);  // f = x
    const TransferFunction tf({{0, 0, 0.5, 1, a}, {1, 1, 0.5, 0, a}});  // r = x, g = 0.5, b = 1 - x
    const ViewTransform view = make_view(ortho_front(48, 48), box[0], box[1]);
    RayCastParams p;
    p.step = 0.02;
    p.ref_step = ref;
    p.termination = 1.0;
    const RgbaImage img = ray_cast_rgba(f, box, view, tf, p, nullptr, 2);
    const double A = 1 - std::pow(1 - a, D / ref);
    int checked = 0;
    for (int j = 0; j < 48; ++j)
        for (int i = 0; i < 48; ++i) {
            const Vec3 w = pixel_world(view, i, j);
            if (w.x < 0.02 || w.x > 0.98 || w.y < 0.02 || w.y > 0.98) continue;
            ++checked;
            // table lookup: within 1/4096 of the value range
            CHECK(px(img, i, j)[0] == Approx(w.x * A).margin(5e-4));
            CHECK(px(img, i, j)[1] == Approx(0.5 * A).margin(5e-4));
            CHECK(px(img, i, j)[2] == Approx((1 - w.x) * A).margin(5e-4));
            CHECK(px(img, i, j)[3] == Approx(A).margin(1e-5));
        }
    CHECK(checked > 300);
}

TEST_CASE("ray casting a field linear along the rays matches the emission-absorption integral, front to back", "[render]") {
    // f = z; the eye looks down -z, so a ray meets z = D first. Colour r = z / D, constant opacity:
    // C = int_0^D (1 - s/D) k e^{-k s} ds with k = -ln(1 - a) / ref_step (s = depth into the box).
    const double D = 1.0, a = 0.1, ref = 0.05;
    const std::array<Vec3, 2> box{Vec3{0, 0, 0}, Vec3{1, 1, D}};
    const LinearField f(0, {0, 0, 1}, box);
    const TransferFunction tf({{0, 0, 0, 0, a}, {D, 1, 1, 1, a}});
    const ViewTransform view = make_view(ortho_front(16, 16), box[0], box[1]);
    RayCastParams p;
    p.step = 0.002;
    p.ref_step = ref;
    p.termination = 1.0;
    const RgbaImage img = ray_cast_rgba(f, box, view, tf, p, nullptr, 1);
    const double k = -std::log(1 - a) / ref, E = std::exp(-k * D);
    const double want = (1 - E) - (1 - E * (1 + k * D)) / (k * D);
    const double back_to_front = (1 - E * (1 + k * D)) / (k * D);  // what the opposite order would give
    REQUIRE(std::abs(want - back_to_front) > 0.2);
    CHECK(px(img, 8, 8)[0] == Approx(want).margin(1e-3));
    CHECK(px(img, 8, 8)[3] == Approx(1 - E).margin(1e-5));
}

TEST_CASE("compositing a single slab seen obliquely gives the analytic opacity of its path length", "[render]") {
    const double d = 0.1, a = 0.25, ref = 0.04, theta = 30;
    const std::array<Vec3, 2> box{Vec3{-5, -5, 0}, Vec3{5, 5, d}};
    const LinearField f(1, {0, 0, 0}, box);
    const TransferFunction tf({{0, 1, 1, 1, a}, {2, 1, 1, 1, a}});
    Camera cam = ortho_front(33, 33);
    cam.azimuth_deg = theta;
    cam.zoom = 4;
    const ViewTransform view = make_view(cam, box[0], box[1]);
    RayCastParams p;
    p.step = 0.003;
    p.ref_step = ref;
    p.termination = 1.0;
    const RgbaImage img = ray_cast_rgba(f, box, view, tf, p, nullptr, 1);
    const double L = d / std::cos(theta * 3.14159265358979323846 / 180);
    CHECK(px(img, 16, 16)[3] == Approx(1 - std::pow(1 - a, L / ref)).margin(1e-5));
}

TEST_CASE("opacity correction: half the step gives nearly the same picture", "[render]") {
    const Volume vol = blob_volume(24);
    const TrilinearField f(vol.view());
    const auto box = f.bounds();
    const TransferFunction tf = transfer_function_preset("viridis", -0.3, 1.3);
    Camera cam;
    cam.width = cam.height = 96;
    const ViewTransform view = make_view(cam, box[0], box[1]);
    RayCastParams p;
    p.ref_step = 0.5 * vol.grid.spacing[0];
    p.step = p.ref_step;
    const Image full = compose_over_background(ray_cast_rgba(f, box, view, tf, p, nullptr, 2), p.background);
    p.step = 0.5 * p.ref_step;
    const Image half = compose_over_background(ray_cast_rgba(f, box, view, tf, p, nullptr, 2), p.background);
    p.step = 0.25 * p.ref_step;
    const Image quarter = compose_over_background(ray_cast_rgba(f, box, view, tf, p, nullptr, 2), p.background);
    // the same picture within sampling error; without the correction the opacity would double
    CHECK(compare_images(full, half).psnr > 40);
    CHECK(compare_images(half, quarter).psnr > 45);
    CHECK(compare_images(half, quarter).rmse < compare_images(full, half).rmse);
    // the check above can fail: uncorrected opacities (a per sample, whatever the step) differ
    p.step = 0.5 * p.ref_step;
    p.ref_step = p.step;  // a per half step: twice the optical depth
    const Image uncorrected = compose_over_background(ray_cast_rgba(f, box, view, tf, p, nullptr, 2), p.background);
    CHECK(compare_images(full, uncorrected).psnr < 35);
}

/// The blob volume of 40^3 samples through its trilinear field, its 8-cell empty-space boxes and
/// the ct-bone transfer function over its values: the scene of the skipping and in-parts tests.
struct BlobScene {
    Volume vol = blob_volume(40);
    TrilinearField f{vol.view()};
    std::array<Vec3, 2> box = f.bounds();
    ValueBoundsGrid skip = value_bounds_from_blocks(block_minmax(vol.view(), 8), vol.grid);
    TransferFunction tf = transfer_function_preset("ct-bone", -0.3, 1.3);
};

TEST_CASE("empty-space skipping of a volume leaves the picture unchanged, and skips", "[render]") {
    const BlobScene scene;
    const auto& [vol, f, box, skip, tf] = scene;
    Camera cam;
    cam.width = cam.height = 80;
    const ViewTransform view = make_view(cam, box[0], box[1]);
    RayCastParams p;
    p.ref_step = p.step = 0.5 * vol.grid.spacing[0];
    for (bool shade : {false, true}) {
        p.shade = shade;
        RayCastStats with, without;
        const RgbaImage a = ray_cast_rgba(f, box, view, tf, p, &skip, 1, &with);
        const RgbaImage b = ray_cast_rgba(f, box, view, tf, p, nullptr, 1, &without);
        CHECK(a.rgba == b.rgba);
        CHECK(with.skipped > 0);
        CHECK(with.samples < without.samples);
        CHECK(with.samples + with.skipped >= without.samples);  // terminated rays stop both alike
    }
}

TEST_CASE("empty-space skipping of a meshless field changes the picture by less than the tolerance", "[render]") {
    // mpu field of 3000 scattered samples of the blob; bounds from the points padded by the support
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(-1, 1);
    PointSet pts;
    for (int i = 0; i < 3000; ++i) {
        const Vec3 q{u(rng), u(rng), u(rng)};
        pts.pos.push_back(q);
        pts.value.push_back(std::exp(-4 * dot(q, q)));
    }
    pts.blocks.push_back({"points", {3000, 1, 1}, 0, 3000});
    FieldParams fp;
    fp.kind = FieldKind::mpu;
    const auto field = make_field(pts, fp);
    const auto box = pts.bounds();
    const double h = mean_point_spacing(pts.pos);
    const ValueBoundsGrid skip = value_bounds_from_points(pts.pos, pts.value, box, 4 * h, 3 * h, 0.05);
    const TransferFunction tf({{0, 0, 0, 0, 0}, {0.45, 0.2, 0.4, 1, 0}, {0.6, 1, 0.9, 0.2, 0.6}, {1, 1, 1, 1, 0.9}});
    Camera cam;
    cam.width = cam.height = 64;
    const ViewTransform view = make_view(cam, box[0], box[1]);
    RayCastParams p;
    p.ref_step = p.step = 0.5 * h;
    RayCastStats with, without;
    const Image a = compose_over_background(ray_cast_rgba(*field, box, view, tf, p, &skip, 2, &with), p.background);
    const Image b = compose_over_background(ray_cast_rgba(*field, box, view, tf, p, nullptr, 2, &without), p.background);
    CHECK(with.skipped > 0);
    CHECK(with.samples < without.samples);
    const ImageDifference d = compare_images(a, b);
    INFO("RMSE " << d.rmse << " max " << d.max_abs);
    CHECK(d.psnr > 45);
    CHECK(d.max_abs <= 8);
}

TEST_CASE("ray casting gives the same bytes for any thread count and tile size", "[render]") {
    const Volume vol = blob_volume(20);
    const TrilinearField f(vol.view());
    const auto box = f.bounds();
    const ValueBoundsGrid skip = value_bounds_from_blocks(block_minmax(vol.view(), 8), vol.grid);
    const TransferFunction tf = transfer_function_preset("ct-skin", -0.3, 1.3);
    Camera cam;
    cam.width = 77;
    cam.height = 53;
    const ViewTransform view = make_view(cam, box[0], box[1]);
    RayCastParams p;
    p.ref_step = p.step = 0.5 * vol.grid.spacing[0];
    p.shade = true;
    const RgbaImage one = ray_cast_rgba(f, box, view, tf, p, &skip, 1);
    for (int t : {2, 3, 4}) CHECK(ray_cast_rgba(f, box, view, tf, p, &skip, t).rgba == one.rgba);
    p.tile = 7;
    CHECK(ray_cast_rgba(f, box, view, tf, p, &skip, 3).rgba == one.rgba);
}

TEST_CASE("early ray termination stops opaque rays after their first sample", "[render]") {
    const std::array<Vec3, 2> box{Vec3{0, 0, 0}, Vec3{1, 1, 1}};
    const LinearField f(0.5, {0, 0, 0}, box);
    const TransferFunction tf({{0.5, 1, 0, 0, 1.0}});
    const ViewTransform view = make_view(ortho_front(32, 32), box[0], box[1]);
    RayCastParams p;
    p.ref_step = p.step = 0.01;
    RayCastStats st;
    const RgbaImage img = ray_cast_rgba(f, box, view, tf, p, nullptr, 1, &st);
    CHECK(st.rays == 32u * 32u);
    CHECK(st.terminated == st.rays_hit);
    // batches start at 8 samples: at most 8 per opaque ray, not 100
    CHECK(st.samples <= 8 * st.rays_hit);
    CHECK(px(img, 16, 16)[0] == 1.0f);
    CHECK(px(img, 16, 16)[3] == 1.0f);
}

TEST_CASE("ray caster parameters are checked", "[render]") {
    const std::array<Vec3, 2> box{Vec3{0, 0, 0}, Vec3{1, 1, 1}};
    const LinearField f(0.5, {0, 0, 0}, box);
    const TransferFunction tf({{0.5, 1, 0, 0, 1.0}});
    const ViewTransform view = make_view(ortho_front(4, 4), box[0], box[1]);
    RayCastParams p;
    p.ref_step = 0.1;
    p.step = 0;
    CHECK_THROWS_AS(ray_cast_rgba(f, box, view, tf, p, nullptr, 1), InvalidArgument);
    p.step = std::nan("");
    CHECK_THROWS_AS(ray_cast_rgba(f, box, view, tf, p, nullptr, 1), InvalidArgument);
    p.step = 1e-9;  // 10^9 samples per ray
    CHECK_THROWS_AS(ray_cast_rgba(f, box, view, tf, p, nullptr, 1), InvalidArgument);
    p.step = 0.1;
    p.ref_step = -1;
    CHECK_THROWS_AS(ray_cast_rgba(f, box, view, tf, p, nullptr, 1), InvalidArgument);
    p.ref_step = 0.1;
    p.termination = 0;
    CHECK_THROWS_AS(ray_cast_rgba(f, box, view, tf, p, nullptr, 1), InvalidArgument);
}

TEST_CASE("cells no scattered point reaches stay outside the picture, with or without skipping", "[render]") {
    // points fill x < 0 of the box [-1, 1]^3; the field extrapolates into x > 0
    std::mt19937 rng(4);
    std::uniform_real_distribution<double> u(-1, 1), half(-1, 0);
    PointSet pts;
    for (int i = 0; i < 2000; ++i) {
        const Vec3 q{half(rng), u(rng), u(rng)};
        pts.pos.push_back(q);
        pts.value.push_back(1 + q.x);
    }
    pts.blocks.push_back({"points", {2000, 1, 1}, 0, 2000});
    FieldParams fp;
    fp.kind = FieldKind::mpu;
    fp.mpu_blend_alpha = 1e9;  // blend over the whole (grown) fit spheres: the field reaches far into x > 0
    const auto field = make_field(pts, fp);
    const std::array<Vec3, 2> box{Vec3{-1, -1, -1}, Vec3{1, 1, 1}};
    const double h = mean_point_spacing(pts.pos);
    ValueBoundsGrid grid = value_bounds_from_points(pts.pos, pts.value, box, 4 * h, 3 * h, 0.05);
    const TransferFunction tf({{-10, 1, 1, 1, 0.3}, {10, 1, 1, 1, 0.3}});  // everything shows
    const ViewTransform view = make_view(ortho_front(40, 40), box[0], box[1]);
    RayCastParams p;
    p.ref_step = p.step = 0.5 * h;
    const RgbaImage with = ray_cast_rgba(*field, box, view, tf, p, &grid, 1);
    const RgbaImage without = ray_cast_rgba(*field, box, view, tf, p, nullptr, 1);
    // every cell with data "unknown" (what meshless render --no-skip passes): the same picture
    for (std::size_t c = 0; c < grid.vmin.size(); ++c)
        if (!(grid.vmin[c] > grid.vmax[c])) grid.vmin[c] = grid.vmax[c] = std::nan("");
    const RgbaImage unknown = ray_cast_rgba(*field, box, view, tf, p, &grid, 1);
    CHECK(unknown.rgba == with.rgba);
    int far = 0, shell = 0;
    for (int j = 0; j < 40; ++j)
        for (int i = 0; i < 40; ++i) {
            const Vec3 w = pixel_world(view, i, j);
            if (w.y < -0.95 || w.y > 0.95 || std::abs(w.x) > 0.95) continue;
            if (w.x < -0.3) CHECK(px(with, i, j)[3] > 0.5f);  // data: drawn
            if (w.x > 0.8) {                                   // beyond pad + a cell: nothing
                ++far;
                CHECK(px(with, i, j)[3] == 0.0f);
                shell += px(without, i, j)[3] > 0.5f;  // the extrapolated shell the cells keep out
            }
        }
    CHECK(far > 10);
    CHECK(shell > far / 2);
}

TEST_CASE("shading a volume by central differences is smooth: nearer the function's own shading than the cells' gradients", "[render]") {
    // A coarse grid (12^3) of a smooth function: shaded with the trilinear interpolant's own
    // gradient every cell is a facet; central differences over one voxel follow the function's
    // gradient. Same values, same opacities: only the shading differs.
    const Volume vol = blob_volume(12);
    const TrilinearField f(vol.view());
    const BlobField blob;
    const ValuesWithGradients exact(f, blob);  // the grid's values, the function's own gradients
    const auto box = f.bounds();
    const TransferFunction tf = transfer_function_preset("ct-bone", -0.3, 1.3);
    Camera cam;
    cam.width = cam.height = 96;
    const ViewTransform view = make_view(cam, box[0], box[1]);
    RayCastParams p;
    p.shade = true;
    p.ref_step = p.step = 0.25 * vol.grid.spacing[0];
    const RgbaImage truth = ray_cast_rgba(exact, box, view, tf, p, nullptr, 1);
    const RgbaImage cells = ray_cast_rgba(f, box, view, tf, p, nullptr, 1);
    p.gradient_step = {vol.grid.spacing[0], vol.grid.spacing[1], vol.grid.spacing[2]};
    const RgbaImage smooth = ray_cast_rgba(f, box, view, tf, p, nullptr, 2);
    const double e_cells = rgba_rms(cells, truth), e_smooth = rgba_rms(smooth, truth);
    INFO("RMS vs the picture shaded by the function's gradient: cell gradients " << e_cells << ", central differences " << e_smooth);
    CHECK(e_smooth < 0.6 * e_cells);
    // the opacities are the field's values', untouched by the shading
    for (std::size_t i = 3; i < smooth.rgba.size(); i += 4) REQUIRE(smooth.rgba[i] == cells.rgba[i]);
    // skipping and threads change nothing; a linear field's central differences are its gradient
    const ValueBoundsGrid skip = value_bounds_from_blocks(block_minmax(vol.view(), 4), vol.grid);
    CHECK(ray_cast_rgba(f, box, view, tf, p, &skip, 1).rgba == smooth.rgba);
    const LinearField lin(0.2, {0.3, 0.2, 0.1}, box);
    RayCastParams q = p;
    q.gradient_step = {0, 0, 0};
    const RgbaImage own = ray_cast_rgba(lin, box, view, tf, q, nullptr, 1), fd = ray_cast_rgba(lin, box, view, tf, p, nullptr, 1);
    CHECK(rgba_rms(own, fd) < 1e-6);
}

TEST_CASE("a picture cast in parts along z, each ray on from where it stood, has ray_cast_rgba's bytes", "[render]") {
    const BlobScene scene;
    const auto& [vol, f, box, skip, tf] = scene;
    // an orbit from outside the box's z range (every ray falls or every ray rises), from inside it
    // (rays both ways, and some flat), orthographic
    struct View {
        double azimuth, elevation, zoom;
        bool perspective;
    };
    bool both_ways = false;  // (some view has rays of both ways)
    for (const View v : {View{30, 20, 1, true}, View{200, -35, 1, true}, View{90, 0, 3, true}, View{-60, 50, 1, false}}) {
        Camera cam;
        cam.width = 48;
        cam.height = 40;
        cam.azimuth_deg = v.azimuth;
        cam.elevation_deg = v.elevation;
        cam.zoom = v.zoom;
        cam.perspective = v.perspective;
        const ViewTransform view = make_view(cam, box[0], box[1]);
        for (bool shade : {false, true}) {
            for (const ValueBoundsGrid* sk : {&skip, static_cast<const ValueBoundsGrid*>(nullptr)}) {
                INFO("azimuth " << v.azimuth << " elevation " << v.elevation << " shade " << shade << " skip " << (sk != nullptr));
                RayCastParams p;
                p.ref_step = p.step = 0.37 * vol.grid.spacing[0];
                p.shade = shade;
                p.gradient_step = {vol.grid.spacing[0], vol.grid.spacing[1], vol.grid.spacing[2]};
                RayCastStats whole_stats;
                const RgbaImage whole = ray_cast_rgba(f, box, view, tf, p, sk, 1, &whole_stats);
                RayCastParts parts(box, view, tf, p, sk);
                both_ways = both_ways || (parts.pending(true) && parts.pending(false));
                // uneven cuts, rising parts for the rising rays, falling for the others; the ends open (a
                // midpoint may round a hair beyond the box)
                const double z0 = box[0].z, z1 = box[1].z, inf = std::numeric_limits<double>::infinity();
                const std::vector<double> cuts{-inf, z0 + 0.11 * (z1 - z0), z0 + 0.5 * (z1 - z0), z0 + 0.5 * (z1 - z0) + 1e-9, inf};
                for (std::size_t i = 0; i + 1 < cuts.size(); ++i)
                    parts.advance(f, true, {cuts[i], cuts[i + 1]}, i + 2 == cuts.size(), 2);
                for (std::size_t i = cuts.size() - 1; i > 0; --i) parts.advance(f, false, {cuts[i - 1], cuts[i]}, i == cuts.size() - 1, 1);
                CHECK_FALSE(parts.pending(true));
                CHECK_FALSE(parts.pending(false));
                CHECK(parts.image().rgba == whole.rgba);
                // (a batch cut at a part's end evaluates none of the samples a terminated ray leaves)
                CHECK(parts.stats().samples <= whole_stats.samples);
                CHECK(parts.stats().rays_hit == whole_stats.rays_hit);
            }
        }
    }
    CHECK(both_ways);
}
