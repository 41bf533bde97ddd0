// kernels/volume_crop.hpp: the samples inside a world box, corners included, on grids with fractional
// spacing and origin (where a division alone rounds the wrong way), and the cropped volume's samples.
#include <catch2/catch.hpp>

#include <cstring>
#include <limits>

#include "kernels/errors.hpp"
#include "kernels/volume_crop.hpp"

using namespace meshless;

TEST_CASE("crop_voxels keeps exactly the samples whose positions lie in the box", "[kernels][crop]") {
    GridSpec g;
    g.dims = {40, 30, 20};
    g.spacing = {0.1, 0.3, 0.7};
    g.origin = {-1.3, 0.2, 5};
    for (const std::array<double, 6>& box : {std::array<double, 6>{-1.0, 0.5, 5.7, 1.2, 3.2, 12.0}, std::array<double, 6>{-9, -9, -9, 9, 9, 99},
                                             std::array<double, 6>{-1.3, 0.2, 5, -1.2, 0.5, 5.7}}) {
        const VoxelBox b = crop_voxels(g, box, "g");
        for (int a = 0; a < 3; ++a)
            for (std::int64_t i = 0; i < g.dims[a]; ++i) {
                const double x = g.origin[a] + static_cast<double>(i) * g.spacing[a];
                const bool inside = x >= box[a] && x <= box[a + 3];
                INFO("axis " << a << " sample " << i << " at " << x);
                CHECK(inside == (i >= b.lo[a] && i <= b.hi[a]));
            }
        const GridSpec c = cropped_grid(g, b);
        for (int a = 0; a < 3; ++a) {
            CHECK(c.dims[a] == b.hi[a] - b.lo[a] + 1);
            CHECK(c.origin[a] == g.origin[a] + static_cast<double>(b.lo[a]) * g.spacing[a]);
        }
    }
    CHECK_THROWS_AS(crop_voxels(g, {-1.3, 0.2, 5, -1.25, 9, 9}, "g"), InvalidArgument);  // one sample along x
    CHECK_THROWS_AS(crop_voxels(g, {1, 0, 0, 0, 9, 9}, "g"), InvalidArgument);         // lo > hi
    CHECK_THROWS_AS(crop_voxels(g, {0, 0, 0, std::numeric_limits<double>::infinity(), 9, 9}, "g"), InvalidArgument);  // not finite
}

TEST_CASE("crop_volume copies the samples of the box", "[kernels][crop]") {
    Volume v(GridSpec{{5, 4, 3}, {0, 0, 0}, {1, 1, 1}}, SampleType::u16);
    auto* p = reinterpret_cast<std::uint16_t*>(v.bytes.data());
    for (int i = 0; i < 60; ++i) p[i] = static_cast<std::uint16_t>(i);
    const VoxelBox b{{1, 1, 1}, {3, 2, 2}};
    const Volume c = crop_volume(v, b);
    REQUIRE(c.grid.dims == std::array<std::int64_t, 3>{3, 2, 2});
    const auto* q = reinterpret_cast<const std::uint16_t*>(c.bytes.data());
    for (int k = 0; k < 2; ++k)
        for (int j = 0; j < 2; ++j)
            for (int i = 0; i < 3; ++i) CHECK(q[i + 3 * (j + 2 * k)] == (1 + i) + 5 * ((1 + j) + 4 * (1 + k)));
    CHECK(c.grid.origin == std::array<double, 3>{1, 1, 1});
}
