// The depth-first binning rule over points rescanned chunk by chunk (kernels/binning_rule_scan.hpp)
// against the in-memory rule (kernels/scattered_binning_grid.hpp): the same grid, bit for bit, on
// uniform, clustered, duplicated, planar and linear sets, for any chunking and order of the scan.
#include <catch2/catch.hpp>

#include <algorithm>
#include <random>

#include "kernels/binning_rule_scan.hpp"
#include "kernels/errors.hpp"

using namespace meshless;

namespace {

std::array<Vec3, 2> bbox(const std::vector<Vec3>& p) {
    Vec3 lo = p.front(), hi = p.front();
    for (const Vec3& v : p) {
        lo = {std::min(lo.x, v.x), std::min(lo.y, v.y), std::min(lo.z, v.z)};
        hi = {std::max(hi.x, v.x), std::max(hi.y, v.y), std::max(hi.z, v.z)};
    }
    return {lo, hi};
}

// A scan that visits p in chunks of `chunk` points, in reversed order when `reverse`, counting its calls.
PointScan scan_of(const std::vector<Vec3>& p, std::size_t chunk, bool reverse, int& calls) {
    return [&p, chunk, reverse, &calls](const std::function<void(std::span<const Vec3>)>& f) {
        ++calls;
        std::vector<Vec3> q = p;
        if (reverse) std::reverse(q.begin(), q.end());
        for (std::size_t i = 0; i < q.size(); i += chunk) f(std::span<const Vec3>(q.data() + i, std::min(chunk, q.size() - i)));
    };
}

void check_same_grid(const std::vector<Vec3>& p, const BinningGridParams& params = {}) {
    const BinningGrid want = make_binning_grid(p, params);
    for (const auto& [chunk, reverse] : {std::pair<std::size_t, bool>{1000, false}, {7, true}}) {
        int calls = 0;
        const BinningGrid got = make_binning_grid_scanned(scan_of(p, chunk, reverse, calls), p.size(), bbox(p), params);
        CHECK(got.dims == want.dims);
        CHECK(got.level == want.level);
        CHECK(got.rule_level == want.rule_level);
        CHECK(got.coarsened == want.coarsened);
        CHECK(got.degenerate == want.degenerate);
        CHECK(got.origin.x == want.origin.x);
        CHECK(got.origin.y == want.origin.y);
        CHECK(got.origin.z == want.origin.z);
        CHECK(got.cell.x == want.cell.x);
        CHECK(got.cell.y == want.cell.y);
        CHECK(got.cell.z == want.cell.z);
        // one scan per level the rule descends (plus none for the bounds: given)
        CHECK(calls >= 1);
        CHECK(calls <= params.max_depth + 1);
    }
}

}  // namespace

TEST_CASE("binning rule by scans: the in-memory rule's grid on uniform and clustered sets", "[kernels][scattered]") {
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> u(-3.0, 5.0);
    std::normal_distribution<double> g(0.0, 0.05);
    SECTION("uniform") {
        std::vector<Vec3> p(20000);
        for (Vec3& v : p) v = {u(rng), u(rng), 0.5 * u(rng)};
        check_same_grid(p);
    }
    SECTION("three tight clusters and a sparse background (levels far apart)") {
        std::vector<Vec3> p;
        for (int i = 0; i < 3000; ++i) p.push_back({u(rng), u(rng), u(rng)});
        for (const Vec3 c : {Vec3{0, 0, 0}, Vec3{4, 4, 4}, Vec3{2, -2, 3}})
            for (int i = 0; i < 9000; ++i) p.push_back({c.x + g(rng), c.y + g(rng), c.z + g(rng)});
        check_same_grid(p);
    }
    SECTION("duplicates (the depth cap ends the walk) and a far offset") {
        std::vector<Vec3> p;
        for (int i = 0; i < 500; ++i) p.push_back({1e6 + u(rng), 1e6 + u(rng), 1e6 + u(rng)});
        for (int i = 0; i < 500; ++i) p.push_back({1e6 + 1, 1e6 + 1, 1e6 + 1});
        check_same_grid(p);
    }
    SECTION("the --max-cells coarsening") {
        std::vector<Vec3> p(30000);
        for (Vec3& v : p) v = {u(rng), u(rng), u(rng)};
        BinningGridParams params;
        params.max_cells = 1000;
        check_same_grid(p, params);
    }
}

TEST_CASE("binning rule by scans: planar and linear sets split only their extents", "[kernels][scattered]") {
    std::mt19937_64 rng(12);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::vector<Vec3> plane(5000), line(3000);
    for (Vec3& v : plane) v = {u(rng), 2.5, u(rng)};
    for (Vec3& v : line) v = {1.0, 2.0, u(rng)};
    check_same_grid(plane);
    check_same_grid(line);
}

TEST_CASE("binning rule by scans: the in-memory rule's refusals", "[kernels][scattered]") {
    int calls = 0;
    const std::vector<Vec3> one{{1, 2, 3}};
    CHECK_THROWS_AS(make_binning_grid(one), InvalidArgument);
    CHECK_THROWS_AS(make_binning_grid_scanned(scan_of(one, 10, false, calls), 1, bbox(one), {}), InvalidArgument);
}
