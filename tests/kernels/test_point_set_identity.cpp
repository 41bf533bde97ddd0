// The data identity of a point set (kernels/point_set_identity.hpp): the hash is part of the .mlf
// format, so it is pinned to the value of its documented formula, computed independently (Python,
// from the header's description) for a small set.
#include <catch2/catch.hpp>

#include "kernels/point_set_identity.hpp"

using namespace meshless;

TEST_CASE("the identity hash follows its documented formula", "[kernels][identity]") {
    PointSet ps;
    for (int i = 0; i < 5; ++i) {
        ps.pos.push_back({0.5 * i, -1.25 * i, 3.0 + i});
        ps.value.push_back(0.1 * i * i);
    }
    const PointSetIdentity id = point_set_identity(ps);
    CHECK(id.count == 5);
    CHECK(id.hash == 0xc9c5c452201c2ee5ull);  // python3: see the formula in the header
    CHECK(id.bounds[0].y == -5.0);
    CHECK(id.bounds[1].z == 7.0);
    CHECK(id.value_range[1] == Approx(1.6));
    CHECK_THAT(describe_identity(id), Catch::StartsWith("5 points, hash c9c5c452201c2ee5, bounds (0,-5,3)..(2,-0,7)"));  // -1.25 * 0 is -0
    PointSet neg = ps;
    neg.value[0] = -0.0;  // 0.0 and -0.0 are different data
    CHECK_FALSE(point_set_identity(neg).same_data(id));
    CHECK(point_set_identity(PointSet{}).count == 0);
}
