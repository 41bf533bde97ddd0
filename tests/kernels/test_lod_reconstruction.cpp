// Levels of detail worth using: on a small volume with sharp edges, noise and a smooth part, the
// LOD of the default tree (weighted split order, cluster means), reconstructed by the mpu field
// (section 5.5, defaults), is closer to every voxel than a uniform random subsample and a regular
// decimation of the same size reconstructed the same way (kernels/cluster_tree.hpp CbtSplitOrder;
// bench/MEASURED.md, "Levels of detail that beat random samples"). Fails if the method regresses.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>
#include <numeric>
#include <vector>

#include "kernels/cluster_binary_tree.hpp"
#include "kernels/cluster_lod.hpp"
#include "kernels/field_params.hpp"
#include "kernels/make_field.hpp"
#include "kernels/splitmix.hpp"

using namespace meshless;

namespace {

PointSet subset(const PointSet& all, const std::vector<std::size_t>& ids) {
    PointSet s;
    for (std::size_t i : ids) {
        s.pos.push_back(all.pos[i]);
        s.value.push_back(all.value[i]);
    }
    s.value_name = "v";
    s.blocks.push_back(PointSetBlock{"subset", {static_cast<std::int64_t>(ids.size()), 1, 1}, 0, ids.size()});
    return s;
}

double rmse_at_voxels(const PointSet& lod, const PointSet& all) {
    FieldParams fp;
    fp.kind = FieldKind::mpu;
    const auto f = make_field(lod, fp);
    std::vector<double> v(all.size());
    f->evaluate(all.pos, v, {});
    double s = 0;
    std::size_t n = 0;
    for (std::size_t i = 0; i < v.size(); ++i)
        if (std::isfinite(v[i])) {
            s += (v[i] - all.value[i]) * (v[i] - all.value[i]);
            ++n;
        }
    REQUIRE(n > all.size() * 9 / 10);
    return std::sqrt(s / static_cast<double>(n));
}

}  // namespace

TEST_CASE("LOD reconstruction: the default tree's LOD beats random samples and a decimation of its size", "[kernels][cbt]") {
    // 48 x 40 x 32 voxels: a quiet background (0), a ball of 200 with a noisy inside, a smooth ramp on one side
    PointSet all;
    SplitMix rng{2024};
    const int nx = 48, ny = 40, nz = 32;
    for (int k = 0; k < nz; ++k)
        for (int j = 0; j < ny; ++j)
            for (int i = 0; i < nx; ++i) {
                // a ball of radius 11 with an edge blurred over about a voxel, as a scanner's is
                const double r = std::sqrt((i - 18.0) * (i - 18.0) + (j - 20.0) * (j - 20.0) + (k - 16.0) * (k - 16.0));
                double v = 100 * (1 - std::tanh(r - 11)) + (r < 11 ? 10 * (rng.unit() - 0.5) : 0);
                if (i > 34) v = 4.0 * (i - 34) + 2.0 * k;
                all.pos.push_back({double(i), double(j), double(k)});
                all.value.push_back(v);
            }
    all.value_name = "v";
    all.blocks.push_back(PointSetBlock{"grid", {nx, ny, nz}, 0, all.pos.size()});
    const std::size_t n = all.size();
    for (const double frac : {0.02, 0.05}) {
        const std::size_t m = static_cast<std::size_t>(std::llround(frac * static_cast<double>(n)));
        CbtParams p;  // the defaults
        p.max_splits = m - 1;
        const ClusterTree t = build_cluster_tree(all.pos, all.value, p);
        const PointSet lod = lod_point_set(t.nodes, LodMode::count, static_cast<double>(m), "v");
        REQUIRE(lod.size() == m);
        std::vector<std::size_t> ids(n);
        std::iota(ids.begin(), ids.end(), std::size_t{0});
        for (std::size_t i = 0; i < m; ++i) std::swap(ids[i], ids[i + rng.next() % (n - i)]);
        ids.resize(m);
        std::vector<std::size_t> dec(m);
        for (std::size_t i = 0; i < m; ++i) dec[i] = i * n / m;
        const double e_lod = rmse_at_voxels(lod, all), e_rnd = rmse_at_voxels(subset(all, ids), all),
                     e_dec = rmse_at_voxels(subset(all, dec), all);
        INFO("fraction " << frac << ": LOD " << e_lod << ", random " << e_rnd << ", decimation " << e_dec);
        CHECK(e_lod < 0.9 * e_rnd);
        CHECK(e_lod < 0.9 * e_dec);
        // the dissertation's order and fitted values (max error, fit) make a LOD that does worse here
        CbtParams d = p;
        d.order = CbtSplitOrder::max_error;
        d.value = CbtValueKind::fit;
        const ClusterTree td = build_cluster_tree(all.pos, all.value, d);
        const double e_max = rmse_at_voxels(lod_point_set(td.nodes, LodMode::count, static_cast<double>(m), "v"), all);
        INFO("max-error order with fits: " << e_max);
        CHECK(e_lod < e_max);
    }
}
