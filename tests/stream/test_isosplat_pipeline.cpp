// Paradigm (C) iso-splatting through the stage graph, against oracles: analytic fields with known
// isosurfaces, the marching-cubes surface (coverage), and byte identity across thread counts.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <unordered_map>
#include <vector>

#include "kernels/analytic_volumes.hpp"
#include "kernels/marching_cubes.hpp"
#include "kernels/trilinear.hpp"
#include "stream/isosplat_pipeline.hpp"
#include "stream/point_sinks.hpp"

using namespace meshless;

namespace {

std::vector<PointRecord> isosplat(const Volume& v, double iso, Projection mode, int threads,
                                  IsoSplatResult* res = nullptr, bool fused = true) {
    CollectSink sink;
    const IsoSplatResult r = run_isosplat(v.view(), iso, mode, SamplingParams{}, sink, {threads}, fused ? PipelineShape::fused : PipelineShape::two_stage);
    if (res) *res = r;
    return sink.points;
}

/// Fraction of MC vertices within `radius` of some point (grid hashing, exact distances).
double coverage(const Mesh& mesh, const std::vector<PointRecord>& pts, double cell) {
    auto key = [&](double x, double y, double z) {
        const auto ix = static_cast<std::int64_t>(std::floor(x / cell)), iy = static_cast<std::int64_t>(std::floor(y / cell)),
                   iz = static_cast<std::int64_t>(std::floor(z / cell));
        return (ix * 73856093) ^ (iy * 19349663) ^ (iz * 83492791);
    };
    std::unordered_multimap<std::int64_t, std::size_t> bins;
    for (std::size_t i = 0; i < pts.size(); ++i) bins.emplace(key(pts[i].pos[0], pts[i].pos[1], pts[i].pos[2]), i);
    std::size_t covered = 0;
    for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
        const double x = mesh.xyz[3 * v], y = mesh.xyz[3 * v + 1], z = mesh.xyz[3 * v + 2];
        bool ok = false;
        for (int dx = -1; dx <= 1 && !ok; ++dx)
            for (int dy = -1; dy <= 1 && !ok; ++dy)
                for (int dz = -1; dz <= 1 && !ok; ++dz) {
                    auto [b, e] = bins.equal_range(key(x + dx * cell, y + dy * cell, z + dz * cell));
                    for (auto it = b; it != e && !ok; ++it) {
                        const PointRecord& p = pts[it->second];
                        const double d2 = (p.pos[0] - x) * (p.pos[0] - x) + (p.pos[1] - y) * (p.pos[1] - y) +
                                          (p.pos[2] - z) * (p.pos[2] - z);
                        ok = d2 <= static_cast<double>(p.radius) * p.radius;
                    }
                }
        covered += ok;
    }
    return mesh.vertex_count() ? static_cast<double>(covered) / mesh.vertex_count() : 1.0;
}

}  // namespace

TEST_CASE("approximate projection lands on the sphere", "[isosplat]") {
    const Volume v = make_analytic_volume(AnalyticField::sphere, 64);
    const double iso = default_iso(AnalyticField::sphere), voxel = v.grid.spacing[0];
    IsoSplatResult r;
    const auto pts = isosplat(v, iso, Projection::approx, 1, &r);
    REQUIRE(pts.size() > 1000);
    CHECK(r.sampling.active_cells == r.projection.input);
    CHECK(r.projection.output == static_cast<std::int64_t>(pts.size()));
    double sum = 0, worst = 0, angle = 0;
    for (const auto& p : pts) {
        const Vec3 q{p.pos[0], p.pos[1], p.pos[2]};
        const double d = analytic_distance(AnalyticField::sphere, iso, q) / voxel;
        sum += d;
        worst = std::max(worst, d);
        const Vec3 n = -normalized(analytic_gradient(AnalyticField::sphere, q));  // VTK: -grad f
        angle += std::acos(std::clamp(dot(n, Vec3{p.normal[0], p.normal[1], p.normal[2]}), -1.0, 1.0));
        CHECK(std::abs(std::sqrt(p.normal[0] * p.normal[0] + p.normal[1] * p.normal[1] + p.normal[2] * p.normal[2]) - 1) < 1e-5);
    }
    const double mean = sum / pts.size(), mean_deg = angle / pts.size() * 180 / M_PI;
    INFO("mean distance " << mean << " voxel, worst " << worst << ", mean normal error " << mean_deg << " deg");
    CHECK(mean <= 0.02);
    CHECK(worst < 0.5);
    CHECK(mean_deg < 2.0);
}

TEST_CASE("unprojected samples sit at cell centres, farther from the surface", "[isosplat]") {
    const Volume v = make_analytic_volume(AnalyticField::sphere, 48);
    const double iso = default_iso(AnalyticField::sphere), voxel = v.grid.spacing[0];
    const auto none = isosplat(v, iso, Projection::none, 1);
    const auto approx = isosplat(v, iso, Projection::approx, 1);
    double dn = 0, da = 0;
    for (const auto& p : none) dn += analytic_distance(AnalyticField::sphere, iso, {p.pos[0], p.pos[1], p.pos[2]}) / voxel;
    for (const auto& p : approx) da += analytic_distance(AnalyticField::sphere, iso, {p.pos[0], p.pos[1], p.pos[2]}) / voxel;
    CHECK(none.size() >= approx.size());
    CHECK(dn / none.size() > 5 * da / approx.size());
    for (const auto& p : none) {  // centre of a cell: origin + (i + 0.5) * spacing
        const double fi = (p.pos[0] - v.grid.origin[0]) / voxel - 0.5;
        CHECK(std::abs(fi - std::round(fi)) < 1e-3);
    }
}

TEST_CASE("exact projection lands on the trilinear isosurface", "[isosplat]") {
    for (AnalyticField f : {AnalyticField::sphere, AnalyticField::torus, AnalyticField::gyroid, AnalyticField::marschner_lobb}) {
        const Volume v = make_analytic_volume(f, 40);
        const double iso = default_iso(f);
        const auto range = v.value_range();
        IsoSplatResult r;
        const auto pts = isosplat(v, iso, Projection::exact, 1, &r);
        REQUIRE(!pts.empty());
        CHECK(r.projection.missed <= r.projection.input / 100);
        // value recorded = trilinear interpolant at the point (project_sample recomputes it)
        double worst = 0;
        for (const auto& p : pts) worst = std::max(worst, std::abs(p.value - iso));
        INFO(to_string(f) << ": worst |f - iso| " << worst << " of range " << range[1] - range[0]);
        CHECK(worst <= 1e-4 * (range[1] - range[0]));
    }
}

TEST_CASE("points cover the marching-cubes surface (no holes)", "[isosplat]") {
    for (AnalyticField f : {AnalyticField::sphere, AnalyticField::torus, AnalyticField::gyroid}) {
        const Volume v = make_analytic_volume(f, 48);
        const double iso = default_iso(f);
        const auto pts = isosplat(v, iso, Projection::approx, 1);
        const Mesh mesh = marching_cubes(v.view(), iso);
        const double c = coverage(mesh, pts, v.grid.spacing[0]);
        INFO(to_string(f) << ": coverage " << c);
        CHECK(c >= 0.99);
    }
}

TEST_CASE("output bytes do not depend on the thread count nor on fusing generate and project", "[isosplat]") {
    const Volume v = make_analytic_volume(AnalyticField::gyroid, 72);
    for (Projection mode : {Projection::approx, Projection::exact, Projection::none}) {
        const auto one = isosplat(v, 0.0, mode, 1);
        const auto staged = isosplat(v, 0.0, mode, 1, nullptr, false);  // generate and project as two stages
        REQUIRE(staged.size() == one.size());
        CHECK(std::memcmp(staged.data(), one.data(), one.size() * sizeof(PointRecord)) == 0);
        for (int t : {2, 3, 4}) {
            const auto many = isosplat(v, 0.0, mode, t);
            REQUIRE(many.size() == one.size());
            CHECK(std::memcmp(many.data(), one.data(), one.size() * sizeof(PointRecord)) == 0);
        }
    }
}

TEST_CASE("isovalue outside the range gives an empty result, NaN cells are skipped and counted", "[isosplat]") {
    Volume v = make_analytic_volume(AnalyticField::sphere, 32);
    CHECK(isosplat(v, 1e9, Projection::approx, 2).empty());
    float* data = reinterpret_cast<float*>(v.bytes.data());
    // poison one voxel on the surface: its active cells are skipped
    const double iso = default_iso(AnalyticField::sphere);
    std::int64_t hit = -1;
    for (std::int64_t i = 0; i < v.grid.voxel_count() && hit < 0; ++i)
        if (std::abs(data[i] - iso) < v.grid.spacing[0] * 0.5) hit = i;
    REQUIRE(hit >= 0);
    const auto before = isosplat(v, iso, Projection::approx, 1);
    data[hit] = std::numeric_limits<float>::quiet_NaN();
    IsoSplatResult r;
    const auto after = isosplat(v, iso, Projection::approx, 1, &r);
    CHECK(r.sampling.nonfinite_cells > 0);
    CHECK(after.size() < before.size());
    for (const auto& p : after)
        for (float x : p.pos) CHECK(std::isfinite(x));
}
