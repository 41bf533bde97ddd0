// kernels/cell_sampling: the samples and their counts against their plain scalar definition (bytes;
// every cell classified by brute force), and the fused
// sample + approximate projection (two cells per SSE2 step, active cells found 64 at a time from
// per-sample bits) against sample_active_cells followed by project_sample, byte for byte, for every
// sample type, odd row lengths, NaN/Inf corners and any split of the rows.
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "kernels/cell_sampling.hpp"
#include "kernels/iso_threshold.hpp"
#include "kernels/trilinear.hpp"

using namespace meshless;

namespace {

/// Equal sizes and bytes (memcmp is not called on empty arrays: their data() may be null).
template <class R>
bool same_bytes(const std::vector<R>& a, const std::vector<R>& b) {
    return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(R)) == 0);
}

template <class T>
std::vector<T> random_volume(const GridSpec& g, std::mt19937& rng, bool specials) {
    std::vector<T> v(static_cast<std::size_t>(g.dims[0] * g.dims[1] * g.dims[2]));
    if constexpr (std::is_floating_point_v<T>) {
        std::uniform_real_distribution<float> d(-1.0f, 1.0f);
        for (auto& x : v) x = d(rng);
        if (specials)
            for (std::size_t i = 0; i < v.size(); i += 37)
                v[i] = i % 3 == 0 ? std::numeric_limits<T>::quiet_NaN()
                       : i % 3 == 1 ? std::numeric_limits<T>::infinity() : -std::numeric_limits<T>::infinity();
    } else {
        // a smooth ramp plus noise: long runs of inactive cells and runs of active ones
        std::uniform_int_distribution<int> d(-3, 3);
        for (std::int64_t k = 0; k < g.dims[2]; ++k)
            for (std::int64_t j = 0; j < g.dims[1]; ++j)
                for (std::int64_t i = 0; i < g.dims[0]; ++i) {
                    const int base = static_cast<int>(std::lround(100.0 + 90.0 * std::sin(0.11 * i + 0.07 * j - 0.05 * k)));
                    const int x = std::clamp(base + d(rng), 0, 255);
                    v[static_cast<std::size_t>(i + g.dims[0] * (j + g.dims[1] * k))] =
                        static_cast<T>(std::is_signed_v<T> ? x - 128 : x);
                }
    }
    return v;
}

/// The definition of the samples (kernels/cell_sampling.hpp), written out plainly: every cell in
/// row-major order, active by the native-type test, non-finite corners skipped, the centre sample by
/// trilinear() and to_world_gradient() in double, stored as floats. `nonfinite` counts the cells
/// that straddle the isovalue but have a NaN/Inf corner.
template <class T>
std::vector<SampleRecord> reference_samples(const std::vector<T>& v, const GridSpec& g, double iso,
                                            const SamplingParams& sp, std::int64_t& nonfinite) {
    std::vector<SampleRecord> out;
    nonfinite = 0;
    const T t = IsoThreshold<T>(iso).t;
    const std::int64_t nx = g.dims[0], ny = g.dims[1];
    const Vec3 size{g.spacing[0], g.spacing[1], g.spacing[2]};
    const auto& s = g.spacing;
    for (std::int64_t k = 0; k + 1 < g.dims[2]; ++k)
        for (std::int64_t j = 0; j + 1 < ny; ++j)
            for (std::int64_t i = 0; i + 1 < nx; ++i) {
                double c[8];
                int above = 0;
                bool finite = true;
                for (int q = 0; q < 8; ++q) {
                    const T x = v[static_cast<std::size_t>((i + (q & 1)) + nx * ((j + (q >> 1 & 1)) + ny * (k + (q >> 2))))];
                    above += x >= t;
                    finite = finite && std::isfinite(static_cast<double>(x));
                    c[q] = static_cast<double>(x);
                }
                if (above == 0 || above == 8) continue;
                if (!finite) {
                    ++nonfinite;
                    continue;
                }
                const ValueGrad vg = trilinear(c, 0.5, 0.5, 0.5);
                const Vec3 gw = to_world_gradient(vg.grad, size);
                const double lo[3] = {g.origin[0] + static_cast<double>(i + sp.index_offset[0]) * s[0],
                                      g.origin[1] + static_cast<double>(j + sp.index_offset[1]) * s[1],
                                      g.origin[2] + static_cast<double>(k + sp.index_offset[2]) * s[2]};
                SampleRecord r;
                for (int a = 0; a < 3; ++a) {
                    r.pos[a] = static_cast<float>(lo[a] + 0.5 * s[a]);
                    r.cell_lo[a] = static_cast<float>(lo[a]);
                    r.cell_size[a] = static_cast<float>(s[a]);
                }
                r.grad[0] = static_cast<float>(gw.x);
                r.grad[1] = static_cast<float>(gw.y);
                r.grad[2] = static_cast<float>(gw.z);
                r.value = static_cast<float>(vg.value);
                r.radius = static_cast<float>(sp.radius_scale * 0.5 * std::sqrt(s[0] * s[0] + s[1] * s[1] + s[2] * s[2]));
                for (int q = 0; q < 8; ++q) r.corner[q] = static_cast<float>(c[q]);
                out.push_back(r);
            }
    return out;
}

template <class T>
void check_type(SampleType type, const std::vector<double>& isos) {
    std::mt19937 rng(7);
    for (std::int64_t nx : {2, 3, 17, 63, 64, 65, 130})
    for (std::array<std::int64_t, 2> yz : {std::array<std::int64_t, 2>{5, 4}, {2, 7}}) {
        GridSpec g;
        g.dims = {nx, yz[0], yz[1]};
        g.origin = {-1.5, 0.25, 3.0};
        g.spacing = {0.37, 1.1, 0.9};
        for (bool specials : {false, true}) {
            if (specials && !std::is_floating_point_v<T>) continue;
            const std::vector<T> data = random_volume<T>(g, rng, specials);
            const VolumeView view{data.data(), type, g};
            const std::int64_t rows = cell_row_count(g);
            for (double iso : isos) {
                CAPTURE(nx, specials, iso);
                SamplingParams sp;
                sp.index_offset = {3, 0, 2};
                sp.radius_scale = 1.5;
                std::vector<SampleRecord> samples;
                SamplingStats s1;
                sample_active_cells(view, iso, 0, rows, sp, samples, s1);
                std::int64_t nonfinite = 0;
                const std::vector<SampleRecord> ref = reference_samples(data, g, iso, sp, nonfinite);
                REQUIRE(samples.size() == ref.size());
                CHECK(same_bytes(samples, ref));
                std::vector<PointRecord> expect;
                ProjectionStats p1;
                for (const SampleRecord& s : samples) {
                    PointRecord p;
                    if (project_sample(s, iso, Projection::approx, p, p1)) expect.push_back(p);
                }
                // fused, and the samples again, the rows in uneven pieces (a piece may start and end
                // mid-slice or span slices)
                std::vector<PointRecord> got;
                std::vector<SampleRecord> pieces;
                SamplingStats s2, s3;
                ProjectionStats p2;
                for (std::int64_t r = 0; r < rows;) {
                    const std::int64_t r1 = std::min(rows, r + 1 + (r % 3) * (r % 5));
                    sample_and_project_active_cells(view, iso, r, r1, sp, Projection::approx, got, s2, p2);
                    sample_active_cells(view, iso, r, r1, sp, pieces, s3);
                    r = r1;
                }
                REQUIRE(pieces.size() == samples.size());
                CHECK(same_bytes(pieces, samples));
                CHECK(s3.active_cells == s1.active_cells);
                REQUIRE(got.size() == expect.size());
                CHECK(same_bytes(got, expect));
                CHECK(s2.active_cells == s1.active_cells);
                CHECK(s2.nonfinite_cells == s1.nonfinite_cells);
                CHECK(p2.input == p1.input);
                CHECK(p2.output == p1.output);
                CHECK(p2.too_far == p1.too_far);
                CHECK(p2.flat == p1.flat);
                CHECK(s1.active_cells == static_cast<std::int64_t>(ref.size()));
                CHECK(s1.nonfinite_cells == nonfinite);
                if (nx >= 63 && yz[0] == 5) CHECK(s1.active_cells > 0);  // the fixture crosses every isovalue
            }
        }
    }
}

}  // namespace

TEST_CASE("cell sampling: active cells as brute force, fused approx projection = sample + project, bytes and counts",
          "[kernels][cell_sampling]") {
    SECTION("u8") { check_type<std::uint8_t>(SampleType::u8, {40.5, 100.0, 187.25}); }
    SECTION("i16") { check_type<std::int16_t>(SampleType::i16, {-60.5, 0.0, 50.5}); }
    SECTION("u16") { check_type<std::uint16_t>(SampleType::u16, {40.5, 100.0, 187.25}); }
    SECTION("f32") { check_type<float>(SampleType::f32, {-0.3, 0.0, 0.51}); }
}

TEST_CASE("cell sampling: a saddle cell with zero gradient at its centre is dropped as flat, in both paths",
          "[kernels][cell_sampling]") {
    // corners 0 1 1 0 / 1 0 0 1 (index dx + 2 dy + 4 dz): every edge average is 0.5, the gradient 0
    const std::uint8_t c[8] = {0, 1, 1, 0, 1, 0, 0, 1};
    GridSpec g;
    g.dims = {2, 2, 2};
    const VolumeView view{c, SampleType::u8, g};
    std::vector<SampleRecord> samples;
    SamplingStats s1, s2;
    sample_active_cells(view, 0.5, 0, 1, SamplingParams{}, samples, s1);
    REQUIRE(samples.size() == 1);
    CHECK(samples[0].grad[0] == 0.0f);
    CHECK(samples[0].grad[1] == 0.0f);
    CHECK(samples[0].grad[2] == 0.0f);
    PointRecord p;
    ProjectionStats p1, p2;
    CHECK_FALSE(project_sample(samples[0], 0.5, Projection::approx, p, p1));
    CHECK(p1.flat == 1);
    std::vector<PointRecord> fused;
    sample_and_project_active_cells(view, 0.5, 0, 1, SamplingParams{}, Projection::approx, fused, s2, p2);
    CHECK(fused.empty());
    CHECK(p2.flat == 1);
    CHECK(p2.input == 1);
    CHECK(s2.active_cells == 1);
}
