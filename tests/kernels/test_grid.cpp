// Volume storage and value ranges (kernels/grid.hpp, kernels/sample_bytes.hpp): the vectorised
// value_range against a brute-force oracle for every sample type, NaN/Inf skipped; SampleBytes
// ownership rules (copies never share adopted memory, resize copies adopted bytes first).
#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>

#include "kernels/grid.hpp"

using namespace meshless;

namespace {

template <class T>
Volume volume_of(const std::vector<T>& vals, SampleType t) {
    Volume v(GridSpec{{static_cast<std::int64_t>(vals.size()), 1, 1}}, t);
    std::memcpy(v.bytes.data(), vals.data(), vals.size() * sizeof(T));
    return v;
}

/// The oracle: a plain loop in double over finite samples.
std::array<double, 2> brute_range(const Volume& v) {
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (std::int64_t i = 0; i < v.grid.voxel_count(); ++i) {
        const double x = v.view().at(i);
        if (!std::isfinite(x)) continue;
        lo = std::min(lo, x);
        hi = std::max(hi, x);
    }
    if (lo > hi) return {std::nan(""), std::nan("")};
    return {lo, hi};
}

template <class T>
void check_random(SampleType t, std::size_t n, std::uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_int_distribution<int> d(std::numeric_limits<T>::lowest() / 2, std::numeric_limits<T>::max() / 2);
    std::vector<T> vals(n);
    for (auto& x : vals) x = static_cast<T>(d(rng));
    const Volume v = volume_of(vals, t);
    const auto r = v.value_range(), b = brute_range(v);
    CHECK(r[0] == b[0]);
    CHECK(r[1] == b[1]);
}

}  // namespace

TEST_CASE("value_range of integer volumes equals a brute-force pass", "[grid]") {
    for (std::size_t n : {1u, 7u, 16u, 33u, 1000u, 4099u}) {
        check_random<std::uint8_t>(SampleType::u8, n, 1);
        check_random<std::int16_t>(SampleType::i16, n, 2);
        check_random<std::uint16_t>(SampleType::u16, n, 3);
    }
    // extremes of each type, at the ends and in the middle of a vector-width run
    const Volume a = volume_of(std::vector<std::uint8_t>{7, 0, 9, 255, 3}, SampleType::u8);
    CHECK(a.value_range() == std::array<double, 2>{0, 255});
    const Volume b = volume_of(std::vector<std::int16_t>{5, -32768, 32767, 0}, SampleType::i16);
    CHECK(b.value_range() == std::array<double, 2>{-32768, 32767});
    const Volume c = volume_of(std::vector<std::uint16_t>(40, 65535), SampleType::u16);
    CHECK(c.value_range() == std::array<double, 2>{65535, 65535});
}

TEST_CASE("value_range of float volumes skips NaN and infinities", "[grid]") {
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    std::vector<float> vals(67, 1.5f);
    vals[0] = nan;
    vals[3] = -inf;
    vals[17] = -2.25f;
    vals[40] = inf;
    vals[41] = 8.0f;
    vals[66] = nan;
    const Volume v = volume_of(vals, SampleType::f32);
    CHECK(v.value_range() == std::array<double, 2>{-2.25, 8.0});
    CHECK(brute_range(v) == v.value_range());
    // the largest finite floats count, their neighbours beyond do not
    const Volume m = volume_of(std::vector<float>{std::numeric_limits<float>::max(), -std::numeric_limits<float>::max(), inf},
                               SampleType::f32);
    CHECK(m.value_range() == std::array<double, 2>{-std::numeric_limits<float>::max(), std::numeric_limits<float>::max()});
    // no finite sample, and no sample at all: {NaN, NaN}
    const Volume all_bad = volume_of(std::vector<float>{nan, inf, -inf, nan}, SampleType::f32);
    CHECK(std::isnan(all_bad.value_range()[0]));
    CHECK(std::isnan(all_bad.value_range()[1]));
    CHECK(std::isnan(value_range(VolumeView{nullptr, SampleType::u8, GridSpec{{0, 0, 0}}})[0]));
    // random floats with random NaN/Inf against the oracle
    std::mt19937 rng(4);
    std::uniform_real_distribution<float> d(-1e6f, 1e6f);
    std::vector<float> r(5003);
    for (auto& x : r) x = (rng() % 13 == 0) ? nan : (rng() % 17 == 0) ? -inf : d(rng);
    const Volume rv = volume_of(r, SampleType::f32);
    CHECK(rv.value_range() == brute_range(rv));
}

TEST_CASE("SampleBytes: adopted memory is kept alive, copies own their bytes", "[grid]") {
    auto store = std::make_shared<std::vector<std::byte>>(10, std::byte{3});
    SampleBytes a = SampleBytes::adopt(store->data(), store->size(), store);
    std::weak_ptr<std::vector<std::byte>> alive = store;
    store.reset();
    REQUIRE(!alive.expired());  // the SampleBytes holds the owner
    CHECK(a.adopted());
    CHECK(a.size() == 10);
    CHECK(a[9] == std::byte{3});

    SampleBytes copy = a;  // a copy owns a vector: writing it leaves the original alone
    CHECK(!copy.adopted());
    copy[0] = std::byte{7};
    CHECK(a[0] == std::byte{3});
    CHECK(copy != a);
    copy[0] = std::byte{3};
    CHECK(copy == a);

    a[1] = std::byte{5};  // adopted memory is writable in place
    CHECK(alive.lock()->at(1) == std::byte{5});

    a.resize(12);  // resize copies into an owned vector first, new bytes zero
    CHECK(!a.adopted());
    CHECK(a.size() == 12);
    CHECK(a[1] == std::byte{5});
    CHECK(a[11] == std::byte{0});
    CHECK(alive.expired());  // the adopted memory was released

    SampleBytes moved = std::move(a);
    CHECK(moved.size() == 12);
    CHECK(a.empty());  // NOLINT(bugprone-use-after-move): moved-from is empty
}
