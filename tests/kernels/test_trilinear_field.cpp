// TrilinearField against the per-cell trilinear kernel and linear fields.
#include <catch2/catch.hpp>

#include <random>

#include "kernels/trilinear_field.hpp"

using namespace meshless;

TEST_CASE("TrilinearField reproduces linear fields with exact gradients, inside and clamped outside", "[field]") {
    GridSpec g;
    g.dims = {7, 5, 4};
    g.origin = {-1, 2, 0.5};
    g.spacing = {0.5, 1.5, 2};
    Volume v(g, SampleType::f32);
    float* d = reinterpret_cast<float*>(v.bytes.data());
    auto f = [](const Vec3& p) { return 3 * p.x - 2 * p.y + 0.5 * p.z + 7; };
    for (std::int64_t k = 0; k < 4; ++k)
        for (std::int64_t j = 0; j < 5; ++j)
            for (std::int64_t i = 0; i < 7; ++i)
                d[g.index(i, j, k)] = static_cast<float>(f({-1 + 0.5 * i, 2 + 1.5 * j, 0.5 + 2.0 * k}));
    const TrilinearField field(v.view());
    std::mt19937 rng(1);
    std::uniform_real_distribution<double> ux(-2, 3), uy(1, 9), uz(0, 7);
    for (int n = 0; n < 1000; ++n) {
        const Vec3 p{ux(rng), uy(rng), uz(rng)};
        Vec3 gr;
        const double val = field.value(p, &gr);
        CHECK(val == Approx(f(p)).margin(1e-4));
        CHECK(gr.x == Approx(3).margin(1e-4));
        CHECK(gr.y == Approx(-2).margin(1e-4));
        CHECK(gr.z == Approx(0.5).margin(1e-4));
    }
    const auto b = field.bounds();
    CHECK(b[1].x == Approx(2.0));
    CHECK(b[1].z == Approx(6.5));
}
