// Paradigm (A) sample store (ooc/sample_store.hpp): the oracle is paradigm (C) itself — for every
// isovalue, query(iso) must return exactly the samples sample_active_cells generates (positions,
// values, gradients, radius, cell corner and size, as multisets); the store built from a brick store
// equals the one built from the volume byte for byte; reads are limited to candidate buckets; every
// single flipped bit, truncation, wrong magic or version is refused with an error naming the file.
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "kernels/analytic_volumes.hpp"
#include "kernels/cell_interval_sampling.hpp"
#include "kernels/cell_sampling.hpp"
#include "kernels/errors.hpp"
#include "ooc/brick_cache.hpp"
#include "ooc/brick_converter.hpp"
#include "ooc/brick_store.hpp"
#include "ooc/sample_store.hpp"
#include "ooc/slice_source.hpp"
#include "test_paths.hpp"

using namespace meshless;
using meshless::test::TempDir;

namespace {

/// The bytes of a SampleRecord that paradigm (A) must reproduce: everything but the corners.
using Key = std::array<unsigned char, offsetof(SampleRecord, corner)>;

Key key_of(const SampleRecord& s) {
    Key k;
    std::memcpy(k.data(), &s, k.size());
    return k;
}

std::vector<Key> paradigm_c(const Volume& v, double iso, const SamplingParams& p = {}) {
    std::vector<SampleRecord> out;
    SamplingStats st;
    sample_active_cells(v.view(), iso, 0, cell_row_count(v.grid), p, out, st);
    std::vector<Key> keys;
    for (const auto& s : out) keys.push_back(key_of(s));
    std::sort(keys.begin(), keys.end());
    return keys;
}

std::vector<Key> paradigm_a(const SampleStore& store, double iso, const SamplingParams& p = {},
                            std::size_t max_batch = 65536) {
    std::vector<Key> keys;
    bool nan_corners = true, small = true;
    store.query(
        iso,
        [&](std::span<const SampleRecord> b) {
            small = small && !b.empty() && b.size() <= max_batch;
            for (const auto& s : b) {
                keys.push_back(key_of(s));
                for (float c : s.corner) nan_corners = nan_corners && std::isnan(c);
            }
        },
        p, max_batch);
    CHECK(nan_corners);
    CHECK(small);
    std::sort(keys.begin(), keys.end());
    return keys;
}

template <class T>
Volume random_volume(std::array<std::int64_t, 3> dims, SampleType t, double lo, double hi, unsigned seed,
                     double nan_fraction = 0.0) {
    GridSpec g;
    g.dims = dims;
    g.origin = {-3.25, 1.5, 0.125};
    g.spacing = {0.7, 1.3, 2.5};
    Volume v(g, t);
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(lo, hi), p01(0, 1);
    T* d = reinterpret_cast<T*>(v.bytes.data());
    for (std::int64_t i = 0; i < g.voxel_count(); ++i) {
        if constexpr (std::is_floating_point_v<T>) {
            d[i] = p01(rng) < nan_fraction ? std::numeric_limits<T>::quiet_NaN() : static_cast<T>(u(rng));
        } else {
            d[i] = static_cast<T>(std::floor(u(rng)));
        }
    }
    return v;
}

/// Isovalues that exercise integer levels, half levels, exact sample values and the range ends.
std::vector<double> isovalues_for(const Volume& v) {
    const auto r = v.value_range();
    std::vector<double> isos = {r[0], r[1], r[0] - 1, r[1] + 1, 0.5 * (r[0] + r[1])};
    for (double f : {0.1, 0.23, 0.37, 0.5, 0.61, 0.77, 0.9}) {
        const double x = r[0] + f * (r[1] - r[0]);
        isos.push_back(x);
        isos.push_back(std::floor(x));
        isos.push_back(std::floor(x) + 0.5);
    }
    // exact sample values (boundary cases of vmin < iso <= vmax), also for float data
    const VolumeView view = v.view();
    for (std::int64_t i : {std::int64_t{7}, v.grid.voxel_count() / 3, v.grid.voxel_count() / 2})
        if (std::isfinite(view.at(i))) isos.push_back(view.at(i));
    return isos;
}

void check_store_matches_c(const Volume& v, const std::string& path, const SampleStoreParams& params = {}) {
    write_sample_store_from_volume(v.view(), path, "vol.raw", params);
    const auto store = SampleStore::open(path);
    CHECK(store->info().grid == v.grid);
    CHECK(store->info().source == "vol.raw");
    for (double iso : isovalues_for(v)) {
        INFO("iso " << iso);
        const auto c = paradigm_c(v, iso);
        const auto a = paradigm_a(*store, iso);
        CHECK(a.size() == c.size());
        CHECK(a == c);
        CHECK(store->count_upper_bound(iso) >= a.size());
    }
}

/// A SliceSource over an in-memory volume (the converter's input).
class MemorySlices final : public SliceSource {
public:
    explicit MemorySlices(const Volume& v) : v_(v) {}
    const GridSpec& grid() const override { return v_.grid; }
    SampleType type() const override { return v_.type; }
    void read_slices(std::int64_t k, std::int64_t count, std::byte* out) override {
        const std::size_t slice = static_cast<std::size_t>(v_.grid.dims[0] * v_.grid.dims[1]) * sample_size(v_.type);
        std::memcpy(out, v_.bytes.data() + static_cast<std::size_t>(k) * slice, static_cast<std::size_t>(count) * slice);
    }
    std::string name() const override { return "memory"; }

private:
    const Volume& v_;
};

std::string slurp(const std::string& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}
void spit(const std::string& p, const std::string& bytes) {
    std::ofstream out(p, std::ios::binary | std::ios::trunc);
    out << bytes;
}

}  // namespace

TEST_CASE("cell interval samples are paradigm (C)'s samples of the active cells", "[parA]") {
    const Volume v = random_volume<std::uint8_t>({11, 9, 7}, SampleType::u8, 0, 256, 1);
    std::vector<CellIntervalSample> all;
    CellIntervalStats st;
    sample_cell_intervals(v.view(), all_cells(v.grid), {0, 0, 0}, v.grid.origin, all, st);
    CHECK(st.samples + st.constant_cells + st.nonfinite_cells == v.grid.cell_count());
    for (double iso : {10.5, 100.0, 200.25}) {
        std::vector<SampleRecord> c;
        SamplingStats cs;
        sample_active_cells(v.view(), iso, 0, cell_row_count(v.grid), {}, c, cs);
        const double thr = active_threshold(v.type, iso);
        std::size_t n = 0, at = 0;
        for (const auto& s : all) {
            if (!(s.vmin < thr && thr <= s.vmax)) continue;
            // same row-major order as paradigm (C) over the whole volume
            REQUIRE(at < c.size());
            CHECK(std::memcmp(s.pos, c[at].pos, 12) == 0);
            CHECK(std::memcmp(s.grad, c[at].grad, 12) == 0);
            CHECK(s.value == c[at].value);
            const float* k = c[at].corner;
            CHECK(s.vmin == *std::min_element(k, k + 8));
            CHECK(s.vmax == *std::max_element(k, k + 8));
            ++at;
            ++n;
        }
        CHECK(n == c.size());
    }
}

TEST_CASE("sample store queries equal paradigm (C) for integer volumes", "[parA]") {
    TempDir d("parA-int");
    SECTION("uint8, exact levels") {
        const Volume v = random_volume<std::uint8_t>({23, 17, 13}, SampleType::u8, 0, 256, 2);
        check_store_matches_c(v, (d / "u8.mls").string());
        const auto s = SampleStore::open((d / "u8.mls").string());
        CHECK(s->info().exact_levels);
    }
    SECTION("uint8 with a narrow range") {
        const Volume v = random_volume<std::uint8_t>({20, 20, 20}, SampleType::u8, 40, 47, 3);
        check_store_matches_c(v, (d / "u8n.mls").string());
    }
    SECTION("int16, quantised levels (range > 256)") {
        const Volume v = random_volume<std::int16_t>({19, 21, 15}, SampleType::i16, -1000, 3000, 4);
        check_store_matches_c(v, (d / "i16.mls").string());
        const auto s = SampleStore::open((d / "i16.mls").string());
        CHECK_FALSE(s->info().exact_levels);
        CHECK(s->info().levels == 256);
    }
    SECTION("uint16 with few levels") {
        const Volume v = random_volume<std::uint16_t>({16, 16, 16}, SampleType::u16, 0, 65535, 5);
        SampleStoreParams p;
        p.levels = 16;
        check_store_matches_c(v, (d / "u16.mls").string(), p);
    }
}

TEST_CASE("sample store queries equal paradigm (C) for float volumes (boundary buckets, NaN cells)", "[parA]") {
    TempDir d("parA-float");
    SECTION("random float with NaN voxels") {
        const Volume v = random_volume<float>({21, 18, 16}, SampleType::f32, -2.0, 5.0, 6, 0.02);
        check_store_matches_c(v, (d / "f.mls").string());
        const auto s = SampleStore::open((d / "f.mls").string());
        CHECK(s->info().nonfinite_cells > 0);
        CHECK(s->info().sample_count + s->info().constant_cells + s->info().nonfinite_cells ==
              static_cast<std::uint64_t>(v.grid.cell_count()));
    }
    for (AnalyticField f : {AnalyticField::sphere, AnalyticField::torus, AnalyticField::gyroid, AnalyticField::marschner_lobb}) {
        DYNAMIC_SECTION("analytic " << to_string(f)) {
            const Volume v = make_analytic_volume(f, 33);
            for (std::uint32_t levels : {1u, 7u, 256u}) {
                INFO("levels " << levels);
                SampleStoreParams p;
                p.levels = levels;
                check_store_matches_c(v, (d / "a.mls").string(), p);
                const auto store = SampleStore::open((d / "a.mls").string());
                CHECK(paradigm_c(v, default_iso(f)).size() > 100);
                CHECK(paradigm_a(*store, default_iso(f)) == paradigm_c(v, default_iso(f)));
            }
        }
    }
    SECTION("radius scale and small batches") {
        const Volume v = make_analytic_volume(AnalyticField::torus, 40);
        write_sample_store_from_volume(v.view(), (d / "t.mls").string(), "torus");
        const auto store = SampleStore::open((d / "t.mls").string());
        SamplingParams p;
        p.radius_scale = 1.7;
        CHECK(paradigm_a(*store, 0.25, p, 100) == paradigm_c(v, 0.25, p));
        CHECK_THROWS_AS(store->query(std::nan(""), [](std::span<const SampleRecord>) {}), UsageError);
    }
}

TEST_CASE("sample store of a constant volume is empty, and queries outside the range emit nothing", "[parA]") {
    TempDir d("parA-const");
    GridSpec g;
    g.dims = {9, 8, 7};
    Volume v(g, SampleType::u8);
    std::fill(v.bytes.begin(), v.bytes.end(), std::byte{42});
    const auto st = write_sample_store_from_volume(v.view(), (d / "c.mls").string(), "c");
    CHECK(st.samples == 0);
    CHECK(st.constant_cells == static_cast<std::uint64_t>(g.cell_count()));
    const auto s = SampleStore::open((d / "c.mls").string());
    for (double iso : {41.0, 42.0, 42.5, 43.0}) CHECK(paradigm_a(*s, iso).empty());
    s->verify();
}

TEST_CASE("writer memory knobs change nothing: buffer size and virtual brick edge are invisible in queries", "[parA]") {
    TempDir d("parA-buf");
    const Volume v = random_volume<float>({30, 25, 20}, SampleType::f32, 0, 1, 7);
    SampleStoreParams big, tiny;
    tiny.buffer_samples = 97;
    write_sample_store_from_volume(v.view(), (d / "big.mls").string(), "v", big);
    write_sample_store_from_volume(v.view(), (d / "tiny.mls").string(), "v", tiny);
    CHECK(slurp((d / "big.mls").string()) == slurp((d / "tiny.mls").string()));
    SampleStoreParams b8;
    b8.brick_edge = 8;
    write_sample_store_from_volume(v.view(), (d / "b8.mls").string(), "v", b8);
    const auto s1 = SampleStore::open((d / "big.mls").string()), s2 = SampleStore::open((d / "b8.mls").string());
    for (double iso : {0.1, 0.5, 0.93}) CHECK(paradigm_a(*s1, iso) == paradigm_a(*s2, iso));
}

TEST_CASE("sample store from a brick store equals the one from the volume, byte for byte", "[parA]") {
    TempDir d("parA-bricks");
    for (int t = 0; t < 2; ++t) {
        const Volume v = t == 0 ? random_volume<std::uint8_t>({37, 29, 23}, SampleType::u8, 0, 256, 8)
                                : random_volume<float>({37, 29, 23}, SampleType::f32, -1, 1, 9, 0.01);
        MemorySlices src(v);
        ConvertParams cp;
        cp.brick_edge = 8;
        convert_to_brick_store(src, (d / "v.mlb").string(), cp);
        const auto bs = BrickStore::open((d / "v.mlb").string());
        BrickCache cache(*bs, bs->max_brick_bytes() * 2);
        SampleStoreParams p;
        p.brick_edge = 8;
        write_sample_store_from_brick_store(*bs, cache, (d / "b.mls").string(), "vol.raw", p);
        write_sample_store_from_volume(v.view(), (d / "v.mls").string(), "vol.raw", p);
        CHECK(slurp((d / "b.mls").string()) == slurp((d / "v.mls").string()));
        const auto store = SampleStore::open((d / "b.mls").string());
        for (double iso : isovalues_for(v)) CHECK(paradigm_a(*store, iso) == paradigm_c(v, iso));
    }
}

TEST_CASE("a query reads only candidate buckets: time proportional to the active cells", "[parA]") {
    TempDir d("parA-io");
    SECTION("exact levels: bytes read == bytes emitted") {
        const Volume v = random_volume<std::uint8_t>({40, 40, 40}, SampleType::u8, 0, 256, 10);
        write_sample_store_from_volume(v.view(), (d / "u8.mls").string(), "v");
        const auto s = SampleStore::open((d / "u8.mls").string());
        for (double iso : {3.0, 17.5, 128.0, 250.5}) {
            s->reset_stats();
            const auto n = paradigm_a(*s, iso).size();
            const auto st = s->stats();
            CHECK(st.samples_emitted == n);
            CHECK(st.samples_read == n);
            CHECK(st.bytes_read == n * sizeof(CellIntervalSample));
            CHECK(s->count_upper_bound(iso) == n);
        }
    }
    SECTION("quantised levels: only samples with level(vmin) <= level(iso) <= level(vmax) are read") {
        const Volume v = make_analytic_volume(AnalyticField::sphere, 48);
        write_sample_store_from_volume(v.view(), (d / "s.mls").string(), "v");
        const auto s = SampleStore::open((d / "s.mls").string());
        std::vector<CellIntervalSample> all;
        CellIntervalStats cst;
        sample_cell_intervals(v.view(), all_cells(v.grid), {0, 0, 0}, v.grid.origin, all, cst);
        REQUIRE(all.size() == s->info().sample_count);
        for (double iso : {0.2, 0.7, 1.3}) {
            const double thr = active_threshold(v.type, iso);
            const std::uint32_t l = s->level(thr);
            std::uint64_t candidates = 0;
            for (const auto& c : all) candidates += s->level(c.vmin) <= l && l <= s->level(c.vmax);
            s->reset_stats();
            const auto n = paradigm_a(*s, iso).size();
            const auto st = s->stats();
            CHECK(st.samples_read <= candidates);
            CHECK(st.samples_read >= n);
            // a thin shell of the volume: far less than the whole store is read
            CHECK(st.samples_read * 10 < s->info().sample_count);
            CHECK(n * 10 < s->info().sample_count);
            WARN("iso " << iso << ": " << n << " active, " << st.samples_read << " read of " << s->info().sample_count);
        }
    }
}

TEST_CASE("damaged sample stores are refused with an error naming the file", "[parA]") {
    TempDir d("parA-bad");
    const Volume v = random_volume<float>({8, 7, 6}, SampleType::f32, 0, 1, 11);
    const std::string good = (d / "good.mls").string(), bad = (d / "bad.mls").string();
    write_sample_store_from_volume(v.view(), good, "v");
    const std::string bytes = slurp(good);
    REQUIRE(bytes.size() > 1000);
    SampleStore::open(good)->verify();

    auto refused = [&](const std::string& b) {
        spit(bad, b);
        try {
            const auto s = SampleStore::open(bad);
            s->verify();
        } catch (const FormatError& e) {
            CHECK_THAT(e.what(), Catch::Contains(bad));
            return true;
        }
        return false;
    };
    SECTION("a flipped bit anywhere is detected (every header and footer byte, strided elsewhere)") {
        int missed = 0;
        const std::size_t footer = bytes.size() - kSampleStoreFooterBytes;
        for (std::size_t i = 0; i < bytes.size(); i += (i < kSampleStoreHeaderBytes || i >= footer) ? 1 : 23) {
            std::string b = bytes;
            b[i] = static_cast<char>(b[i] ^ (1 << (i % 8)));
            if (!refused(b)) ++missed;
        }
        CHECK(missed == 0);
    }
    SECTION("a flipped bit in the samples fails the query that reads them") {
        std::string b = bytes;
        const std::size_t at = kSampleStoreHeaderBytes + 36 * 5 + 3;  // in sample 5
        b[at] = static_cast<char>(b[at] ^ 0x10);
        spit(bad, b);
        const auto s = SampleStore::open(bad);
        std::size_t bucket = 0;
        while (!(s->buckets()[bucket].first <= 5 && 5 < s->buckets()[bucket].first + s->buckets()[bucket].count)) ++bucket;
        const double iso = s->buckets()[bucket].max_vmax;
        CHECK_THROWS_WITH(s->query(iso, [](std::span<const SampleRecord>) {}), Catch::Contains("checksum mismatch") && Catch::Contains(bad));
    }
    SECTION("truncation at any length") {
        for (std::size_t n : {std::size_t{0}, std::size_t{5}, std::size_t{100}, std::size_t{256}, std::size_t{300},
                              bytes.size() / 2, bytes.size() - 40, bytes.size() - 32, bytes.size() - 1})
            CHECK(refused(bytes.substr(0, n)));
        CHECK(refused(bytes + "x"));
        spit(bad, bytes.substr(0, bytes.size() - 1));
        CHECK_THROWS_WITH(SampleStore::open(bad), Catch::Contains("truncated"));
    }
    SECTION("wrong magic, wrong version, a point stream") {
        std::string b = bytes;
        b[3] = 'X';
        spit(bad, b);
        CHECK_THROWS_WITH(SampleStore::open(bad), Catch::Contains("not a meshless sample store"));
        CHECK_FALSE(is_sample_store(bad));
        b = bytes;
        b[8] = 2;
        spit(bad, b);
        CHECK_THROWS_WITH(SampleStore::open(bad), Catch::Contains("version 2"));
        b = bytes;
        b[3] = 'S';
        spit(bad, b);
        CHECK_THROWS_WITH(SampleStore::open(bad), Catch::Contains("point stream"));
        CHECK(is_sample_store(good));
    }
    SECTION("missing file and directories are I/O errors") {
        CHECK_THROWS_AS(SampleStore::open((d / "nope.mls").string()), IoError);
        CHECK_THROWS_AS(SampleStore::open(d.path.string()), IoError);
    }
    SECTION("stdout is refused, and a failed write leaves no file") {
        CHECK_THROWS_AS(write_sample_store_from_volume(v.view(), "-", "v"), UsageError);
        SampleStoreParams p;
        p.levels = 0;
        CHECK_THROWS_AS(write_sample_store_from_volume(v.view(), (d / "x.mls").string(), "v", p), UsageError);
        CHECK_FALSE(std::filesystem::exists(d / "x.mls"));
    }
}
