// Paradigm (A) sample store (ooc/sample_store*.hpp, ooc/span_space_levels.hpp, ooc/row_key_*.hpp).
// Oracles: paradigm (C) itself — for every isovalue a query must return exactly the SampleRecords
// that sample_active_cells gives brick by brick in Morton order (same bytes, same order, corners
// included) and, as a multiset, over the whole in-memory volume; writer knobs change no byte;
// reads stay within the candidate buckets and the bricks holding active cells; every defect class
// (magic, version, checksums, truncation, inconsistent table, oversized header claims, missing or
// changed .mlb) is refused with a one-line error naming the file; the in-memory parser (the
// fuzz-friendly entry point) survives random mutations.
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "kernels/analytic_volumes.hpp"
#include "kernels/iso_threshold.hpp"
#include "kernels/cell_sampling.hpp"
#include "kernels/errors.hpp"
#include "ooc/brick_index.hpp"
#include "ooc/brick_store.hpp"
#include "ooc/row_key_codec.hpp"
#include "ooc/row_set.hpp"
#include "ooc/sample_store.hpp"
#include "ooc/sample_store_format.hpp"
#include "ooc/sample_store_writer.hpp"
#include "ooc/span_space_levels.hpp"
#include "ooc_test_util.hpp"
#include "test_paths.hpp"

using namespace meshless;
using meshless::test::TempDir;
using meshless::test::read_bytes;
using meshless::test::write_bytes;

namespace {

using Rec = std::array<unsigned char, sizeof(SampleRecord)>;

Rec rec_of(const SampleRecord& s) {
    Rec k;
    std::memcpy(k.data(), &s, k.size());
    return k;
}

/// Paradigm (C) over a brick store, exactly as BrickGenerateStage runs it: bricks in Morton
/// order, every cell row of each brick, positions from the whole volume.
std::vector<Rec> paradigm_c_bricks(const BrickStore& bs, double iso, const SamplingParams& p0 = {}) {
    std::vector<Rec> out;
    std::vector<std::byte> buf;
    for (std::size_t i = 0; i < bs.bricks().size(); ++i) {
        bs.read_brick(i, buf);
        GridSpec g = bs.brick_grid(i);
        g.origin = bs.info().grid.origin;
        SamplingParams p = p0;
        p.index_offset = bs.brick_first_voxel(i);
        std::vector<SampleRecord> s;
        SamplingStats st;
        sample_active_cells(VolumeView{buf.data(), bs.info().type, g}, iso, 0, cell_row_count(g), p, s, st);
        for (const auto& r : s) out.push_back(rec_of(r));
    }
    return out;
}

/// Paradigm (C) over the whole in-memory volume, as a sorted multiset.
std::vector<Rec> paradigm_c_volume(const Volume& v, double iso) {
    std::vector<SampleRecord> s;
    SamplingStats st;
    sample_active_cells(v.view(), iso, 0, cell_row_count(v.grid), {}, s, st);
    std::vector<Rec> out;
    for (const auto& r : s) out.push_back(rec_of(r));
    std::sort(out.begin(), out.end());
    return out;
}

std::vector<Rec> paradigm_a(const SampleStore& store, double iso, const SamplingParams& p = {}, std::size_t max_batch = 4096) {
    std::vector<Rec> out;
    bool capped = true;
    store.query(
        iso,
        [&](std::span<const SampleRecord> b) {
            capped = capped && !b.empty() && b.size() <= max_batch;
            for (const auto& r : b) out.push_back(rec_of(r));
        },
        p, max_batch);
    CHECK(capped);
    return out;
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
    const VolumeView view = v.view();
    for (std::int64_t i : {std::int64_t{7}, v.grid.voxel_count() / 3, v.grid.voxel_count() / 2})
        if (std::isfinite(view.at(i))) isos.push_back(view.at(i));
    return isos;
}

/// Builds v.mlb (brick edge B) and v.mls in d; checks every isovalue against paradigm (C).
void check_store_matches_c(const TempDir& d, const Volume& v, std::uint32_t B, const SampleStoreParams& params = {}) {
    const std::string mlb = (d / "v.mlb").string(), mls = (d / "v.mls").string();
    meshless::test::convert_volume(v, mlb, B);
    const auto bs = BrickStore::open(mlb);
    write_sample_store(*bs, mls, params);
    const auto store = SampleStore::open(mls);
    CHECK(store->info().grid == v.grid);
    CHECK(store->info().cells + store->info().constant_cells + store->info().nonfinite_cells ==
          static_cast<std::uint64_t>(v.grid.cell_count()));
    for (double iso : isovalues_for(v)) {
        INFO("iso " << iso << ", brick edge " << B);
        const auto a = paradigm_a(*store, iso);
        const auto c = paradigm_c_bricks(*bs, iso);
        CHECK(a.size() == c.size());
        CHECK(a == c);  // same bytes, same order
        auto sorted = a;
        std::sort(sorted.begin(), sorted.end());
        CHECK(sorted == paradigm_c_volume(v, iso));
    }
}

}  // namespace

TEST_CASE("row keys: gap coding round trip and malformed input", "[parA]") {
    std::mt19937_64 rng(1);
    for (int t = 0; t < 50; ++t) {
        const std::uint64_t limit = 1 + rng() % (t < 25 ? 1000 : (std::uint64_t{1} << 40));
        std::vector<std::uint64_t> keys;
        for (int i = 0; i < 200; ++i) keys.push_back(rng() % limit);
        std::sort(keys.begin(), keys.end());
        keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
        std::vector<unsigned char> bytes;
        std::uint64_t last = 0;
        for (auto k : keys) {
            put_varint(bytes, k + 1 - last);
            last = k + 1;
        }
        std::vector<std::uint64_t> back;
        REQUIRE(decode_row_keys(bytes.data(), bytes.data() + bytes.size(), keys.size(), limit, back));
        CHECK(back == keys);
        back.clear();
        CHECK_FALSE(decode_row_keys(bytes.data(), bytes.data() + bytes.size(), keys.size() + 1, limit, back));
        back.clear();
        if (keys.size() > 1)
            CHECK_FALSE(decode_row_keys(bytes.data(), bytes.data() + bytes.size(), keys.size() - 1, limit, back));  // leftover
        back.clear();
        CHECK_FALSE(decode_row_keys(bytes.data(), bytes.data() + bytes.size(), keys.size(), keys.back(), back));  // beyond limit
    }
    std::vector<std::uint64_t> out;
    const unsigned char zero_gap[] = {0};
    CHECK_FALSE(decode_row_keys(zero_gap, zero_gap + 1, 1, 100, out));
    const unsigned char overlong[] = {0x80, 0x80, 0x80, 0x80, 0x80, 0x80, 0x80, 0x80, 0x80, 0x80, 0x01};
    CHECK_FALSE(decode_row_keys(overlong, overlong + sizeof overlong, 1, ~std::uint64_t{0}, out));
    const unsigned char cut[] = {0x81};
    CHECK_FALSE(decode_row_keys(cut, cut + 1, 1, 1000, out));
}

TEST_CASE("row set: merging keys equals sort + unique, iteration ascending", "[parA]") {
    std::mt19937_64 rng(2);
    for (std::uint64_t limit : {std::uint64_t{1}, std::uint64_t{2}, std::uint64_t{63}, std::uint64_t{64},
                                std::uint64_t{65}, std::uint64_t{2048}, std::uint64_t{1} << 22}) {
        for (std::size_t n : {std::size_t{0}, std::size_t{10}, std::size_t{5000}}) {
            std::vector<std::uint64_t> keys;
            for (std::size_t i = 0; i < n; ++i) keys.push_back(rng() % limit);
            RowSet set(limit);
            for (auto k : keys) set.insert(k);
            std::sort(keys.begin(), keys.end());
            keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
            std::vector<std::uint64_t> got;
            for (std::uint64_t k = set.next(0); k < set.limit(); k = set.next(k + 1)) got.push_back(k);
            CHECK(got == keys);
            CHECK(set.size() == keys.size());
            CHECK(set.next(limit) == limit);
            for (auto k : keys) CHECK(set.contains(k));
        }
    }
}

TEST_CASE("span-space candidates hold every active cell", "[parA]") {
    std::mt19937 rng(3);
    for (SampleType t : {SampleType::u8, SampleType::i16, SampleType::f32}) {
        for (std::uint32_t maxl : {1u, 7u, 256u}) {
            const double lo = t == SampleType::i16 ? -500 : 0, hi = t == SampleType::u8 ? 255 : 700;
            const SpanSpaceLevels L = SpanSpaceLevels::make(t, lo, hi, maxl);
            std::uniform_int_distribution<int> u(static_cast<int>(lo), static_cast<int>(hi));
            for (int i = 0; i < 20000; ++i) {
                double a = u(rng), b = u(rng);
                if (a > b) std::swap(a, b);
                const double iso = u(rng) + (i % 3) * 0.5 - 0.25;
                const double thr = active_threshold(t, iso);
                const bool active = a < thr && thr <= b;
                if (active) CHECK(L.candidate(L(a), L(b), thr));
                if (L.exact && L.candidate(L(a), L(b), thr)) CHECK(active);  // exact levels: no false candidates
            }
        }
    }
}

TEST_CASE("sample store queries equal paradigm (C) for integer volumes", "[parA]") {
    TempDir d("parA-int");
    SECTION("uint8, exact levels, several brick edges") {
        const Volume v = random_volume<std::uint8_t>({23, 17, 13}, SampleType::u8, 0, 256, 2);
        for (std::uint32_t B : {4u, 8u, 32u}) check_store_matches_c(d, v, B);
        CHECK(SampleStore::open((d / "v.mls").string())->info().exact_levels);
    }
    SECTION("uint8 with a narrow range") {
        check_store_matches_c(d, random_volume<std::uint8_t>({20, 20, 20}, SampleType::u8, 40, 47, 3), 8);
    }
    SECTION("int16, quantised levels (range > 256)") {
        check_store_matches_c(d, random_volume<std::int16_t>({19, 21, 15}, SampleType::i16, -1000, 3000, 4), 8);
        const auto s = SampleStore::open((d / "v.mls").string());
        CHECK_FALSE(s->info().exact_levels);
        CHECK(s->info().levels == 256);
    }
    SECTION("uint16 with few levels") {
        SampleStoreParams p;
        p.levels = 16;
        check_store_matches_c(d, random_volume<std::uint16_t>({16, 16, 16}, SampleType::u16, 0, 65535, 5), 8, p);
    }
}

TEST_CASE("sample store queries equal paradigm (C) for float volumes (boundary buckets, NaN cells)", "[parA]") {
    TempDir d("parA-float");
    SECTION("random float with NaN voxels") {
        check_store_matches_c(d, random_volume<float>({21, 18, 16}, SampleType::f32, -2.0, 5.0, 6, 0.02), 8);
        CHECK(SampleStore::open((d / "v.mls").string())->info().nonfinite_cells > 0);
    }
    for (AnalyticField f : {AnalyticField::sphere, AnalyticField::torus, AnalyticField::gyroid}) {
        DYNAMIC_SECTION("analytic " << to_string(f)) {
            const Volume v = make_analytic_volume(f, 33);
            for (std::uint32_t levels : {1u, 7u, 256u}) {
                INFO("levels " << levels);
                SampleStoreParams p;
                p.levels = levels;
                check_store_matches_c(d, v, 8, p);
                CHECK(paradigm_c_volume(v, default_iso(f)).size() > 100);
            }
        }
    }
    SECTION("radius scale and small batches") {
        const Volume v = make_analytic_volume(AnalyticField::torus, 40);
        meshless::test::convert_volume(v, (d / "t.mlb").string(), 16);
        const auto bs = BrickStore::open((d / "t.mlb").string());
        write_sample_store(*bs, (d / "t.mls").string());
        const auto store = SampleStore::open((d / "t.mls").string());
        SamplingParams p;
        p.radius_scale = 1.7;
        const auto c = paradigm_c_bricks(*bs, 0.25, p);
        CHECK(c.size() > 1000);
        CHECK(paradigm_a(*store, 0.25, p, 7) == c);
        CHECK(paradigm_a(*store, 0.25, p, 100) == c);
        CHECK_THROWS_AS(store->query(std::nan(""), [](std::span<const SampleRecord>) {}), InvalidArgument);
    }
}

TEST_CASE("sample store of a constant volume is empty, and queries outside the range emit nothing", "[parA]") {
    TempDir d("parA-const");
    GridSpec g;
    g.dims = {9, 8, 7};
    Volume v(g, SampleType::u8);
    std::fill(v.bytes.begin(), v.bytes.end(), std::byte{42});
    meshless::test::convert_volume(v, (d / "c.mlb").string(), 4);
    const auto st = write_sample_store(*BrickStore::open((d / "c.mlb").string()), (d / "c.mls").string());
    CHECK(st.cells == 0);
    CHECK(st.constant_cells == static_cast<std::uint64_t>(g.cell_count()));
    const auto s = SampleStore::open((d / "c.mls").string());
    for (double iso : {41.0, 42.0, 42.5, 43.0}) CHECK(paradigm_a(*s, iso).empty());
    s->verify();
}

TEST_CASE("the writer's buffer size changes no byte of the store", "[parA]") {
    TempDir d("parA-buf");
    const Volume v = random_volume<float>({30, 25, 20}, SampleType::f32, 0, 1, 7);
    meshless::test::convert_volume(v, (d / "v.mlb").string(), 8);
    const auto bs = BrickStore::open((d / "v.mlb").string());
    SampleStoreParams big, tiny;
    tiny.buffer_keys = 3;
    write_sample_store(*bs, (d / "big.mls").string(), big);
    write_sample_store(*bs, (d / "tiny.mls").string(), tiny);
    CHECK(read_bytes(d / "big.mls") == read_bytes(d / "tiny.mls"));
}

TEST_CASE("a query reads only candidate buckets and the bricks holding active cells", "[parA]") {
    TempDir d("parA-io");
    const Volume v = make_analytic_volume(AnalyticField::sphere, 64);
    meshless::test::convert_volume(v, (d / "s.mlb").string(), 8);
    const auto bs = BrickStore::open((d / "s.mlb").string());
    write_sample_store(*bs, (d / "s.mls").string());
    const auto s = SampleStore::open((d / "s.mls").string());
    const BrickIndex index(*bs);
    for (double iso : {0.2, 0.7, 1.3}) {
        s->reset_stats();
        const auto n = paradigm_a(*s, iso).size();
        const auto st = s->stats();
        CHECK(st.samples_emitted == n);
        CHECK(n > 100);
        CHECK(st.bricks_read <= index.active(iso).size());
        // a thin shell of the volume: far less than the whole index is read
        CHECK(st.key_bytes_read * 5 < s->info().key_bytes);
        CHECK(st.rows_read * 8 * 5 < static_cast<std::uint64_t>(v.grid.cell_count()));  // rows of 8 cells
        WARN("iso " << iso << ": " << n << " active, " << st.rows_read << " rows, " << st.bricks_read << " of "
                    << bs->bricks().size() << " bricks, " << st.key_bytes_read << " of " << s->info().key_bytes << " key bytes");
    }
}

TEST_CASE("damaged sample stores are refused with an error naming the file", "[parA]") {
    TempDir d("parA-bad");
    const Volume v = random_volume<std::uint8_t>({12, 11, 10}, SampleType::u8, 0, 256, 11);
    const std::string mlb = (d / "v.mlb").string(), good = (d / "good.mls").string(), bad = (d / "bad.mls").string();
    meshless::test::convert_volume(v, mlb, 4);
    write_sample_store(*BrickStore::open(mlb), good);
    const std::string bytes = read_bytes(good);
    REQUIRE(bytes.size() > 1000);
    SampleStore::open(good)->verify();

    auto error_of = [&](const std::string& b) -> std::string {
        write_bytes(bad, b);
        try {
            SampleStore::open(bad)->verify();
        } catch (const FormatError& e) {
            CHECK_THAT(e.what(), Catch::StartsWith(bad));
            CHECK(std::string(e.what()).find('\n') == std::string::npos);
            return e.what();
        }
        return "";
    };
    const auto hdr = [&](const std::string& b) {  // re-seals the header CRC after an edit
        std::string x = b;
        const std::uint32_t crc = sample_store_crc32(0, x.data(), 508);
        std::memcpy(x.data() + 508, &crc, 4);
        return x;
    };
    SECTION("bad magic, a point stream, another version") {
        std::string b = bytes;
        b[3] = 'X';
        CHECK_THAT(error_of(b), Catch::Contains("not a meshless sample store"));
        CHECK_FALSE(is_sample_store(bad));
        b = bytes;
        b[3] = 'S';
        CHECK_THAT(error_of(b), Catch::Contains("point stream"));
        b = bytes;
        b[8] = 1;
        CHECK_THAT(error_of(b), Catch::Contains("version 1"));
        b = bytes;
        b[8] = 3;
        CHECK_THAT(error_of(hdr(b)), Catch::Contains("version 3"));
    }
    SECTION("bad header, table and bucket checksums") {
        std::string b = bytes;
        b[100] ^= 0x04;
        CHECK_THAT(error_of(b), Catch::Contains("header checksum"));
        b = bytes;
        b[bytes.size() - kSampleStoreFooterBytes - 5] ^= 0x01;  // in the last table entry
        CHECK_THAT(error_of(b), Catch::Contains("table checksum"));
        b = bytes;
        b[kSampleStoreHeaderBytes + 3] ^= 0x10;  // in the first bucket's keys
        CHECK_THAT(error_of(b), Catch::Contains("bucket ") && Catch::Contains("checksum mismatch"));
    }
    SECTION("a damaged bucket fails the query that reads it, before anything is emitted") {
        std::string b = bytes;
        b[kSampleStoreHeaderBytes + 1] ^= 0x10;
        write_bytes(bad, b);
        const auto s = SampleStore::open(bad);  // buckets are checked when read
        const SampleBucket& b0 = s->buckets()[0];
        const double iso = s->info().value_lo + b0.a + 0.5;  // exact levels: bucket 0 is a candidate
        std::size_t emitted = 0;
        CHECK_THROWS_WITH(s->query(iso, [&](std::span<const SampleRecord> r) { emitted += r.size(); }),
                          Catch::Contains("checksum mismatch") && Catch::Contains(bad));
        CHECK(emitted == 0);
    }
    SECTION("truncated at any length, or trailing bytes") {
        for (std::size_t n : {std::size_t{0}, std::size_t{5}, std::size_t{10}, std::size_t{100}, std::size_t{512},
                              std::size_t{600}, bytes.size() / 2, bytes.size() - 40, bytes.size() - 32, bytes.size() - 1})
            CHECK_FALSE(error_of(bytes.substr(0, n)).empty());
        CHECK_THAT(error_of(bytes.substr(0, bytes.size() - 1)), Catch::Contains("truncated"));
        CHECK_THAT(error_of(bytes + "x"), Catch::Contains("trailing"));
    }
    SECTION("header claims beyond the file are refused before allocating") {
        for (std::size_t field : {std::size_t{184}, std::size_t{128}}) {  // key bytes, bucket count
            std::string b = bytes;
            const std::uint64_t huge = std::uint64_t{1} << 60;
            std::memcpy(b.data() + field, &huge, 8);
            CHECK_THAT(error_of(hdr(b)), Catch::Contains("truncated"));
        }
        std::string b = bytes;
        const std::uint64_t huge = std::uint64_t{1} << 62;
        std::memcpy(b.data() + 160, &huge, 8);  // brick count
        CHECK_THAT(error_of(hdr(b)), Catch::Contains("identity"));
    }
    SECTION("an inconsistent table is refused even with a valid checksum") {
        const auto s = SampleStore::open(good);
        REQUIRE(s->buckets().size() >= 2);
        std::string b = bytes;
        const std::size_t table = bytes.size() - kSampleStoreFooterBytes - s->buckets().size() * kSampleStoreBucketBytes;
        SampleBucket e = s->buckets()[1];
        e.offset += 1;  // not contiguous
        encode_sample_store_bucket(e, reinterpret_cast<unsigned char*>(b.data() + table + kSampleStoreBucketBytes));
        const std::uint32_t crc = sample_store_crc32(0, b.data() + table, s->buckets().size() * kSampleStoreBucketBytes);
        std::memcpy(b.data() + bytes.size() - kSampleStoreFooterBytes + 16, &crc, 4);
        CHECK_THAT(error_of(b), Catch::Contains("inconsistent bucket 1"));
    }
    SECTION("a flipped bit anywhere is detected (every header/footer byte, strided elsewhere)") {
        int missed = 0;
        const std::size_t footer = bytes.size() - kSampleStoreFooterBytes;
        for (std::size_t i = 0; i < bytes.size(); i += (i < kSampleStoreHeaderBytes || i >= footer) ? 1 : 7) {
            std::string b = bytes;
            b[i] = static_cast<char>(b[i] ^ (1 << (i % 8)));
            if (error_of(b).empty()) ++missed;
        }
        CHECK(missed == 0);
    }
    SECTION("missing or changed brick store") {
        std::filesystem::rename(mlb, (d / "moved.mlb").string());
        CHECK_THAT(error_of(bytes), Catch::Contains("v.mlb") && Catch::Contains("missing"));
        std::filesystem::rename((d / "moved.mlb").string(), mlb);
        meshless::test::convert_volume(random_volume<std::uint8_t>({12, 11, 10}, SampleType::u8, 0, 256, 12), mlb, 4);
        CHECK_THAT(error_of(bytes), Catch::Contains("v.mlb") && Catch::Contains("changed"));
        write_bytes(mlb, "not a brick store at all");
        CHECK_FALSE(error_of(bytes).empty());
    }
    SECTION("the store may move together with its brick store (relative reference)") {
        std::filesystem::create_directories(d / "sub");
        std::filesystem::rename(mlb, d / "sub" / "v.mlb");
        write_bytes(d / "sub" / "s.mls", bytes);
        const auto s = SampleStore::open((d / "sub" / "s.mls").string());
        CHECK(paradigm_a(*s, 100.5) == paradigm_c_bricks(s->brick_store(), 100.5));
    }
    SECTION("missing file and directories are I/O errors; stdout and bad levels are usage errors") {
        CHECK_THROWS_AS(SampleStore::open((d / "nope.mls").string()), IoError);
        CHECK_THROWS_AS(SampleStore::open(d.path.string()), IoError);
        const auto bs = BrickStore::open(mlb);
        CHECK_THROWS_AS(write_sample_store(*bs, "-"), InvalidArgument);
        SampleStoreParams p;
        p.levels = 0;
        CHECK_THROWS_AS(write_sample_store(*bs, (d / "x.mls").string(), p), InvalidArgument);
        CHECK_FALSE(std::filesystem::exists(d / "x.mls"));
    }
}

TEST_CASE("the in-memory parser (fuzz entry point) accepts good stores and survives mutations", "[parA]") {
    TempDir d("parA-fuzz");
    const Volume v = random_volume<std::uint8_t>({10, 9, 8}, SampleType::u8, 0, 256, 13);
    meshless::test::convert_volume(v, (d / "v.mlb").string(), 4);
    write_sample_store(*BrickStore::open((d / "v.mlb").string()), (d / "v.mls").string());
    const std::string s = read_bytes(d / "v.mls");
    const auto span = [](const std::string& b) {
        return std::span<const unsigned char>(reinterpret_cast<const unsigned char*>(b.data()), b.size());
    };
    const SampleStoreLayout l = parse_sample_store_bytes(span(s), "mem");
    CHECK(l.buckets.size() == SampleStore::open((d / "v.mls").string())->buckets().size());
    std::mt19937 rng(14);
    int accepted = 0;
    for (int t = 0; t < 3000; ++t) {
        std::string b = s;
        const int edits = 1 + static_cast<int>(rng() % 4);
        for (int e = 0; e < edits; ++e) {
            switch (rng() % 3) {
                case 0: b[rng() % b.size()] = static_cast<char>(rng()); break;
                case 1: b.resize(rng() % (b.size() + 1)); break;
                default: b.insert(rng() % (b.size() + 1), 1, static_cast<char>(rng())); break;
            }
            if (b.empty()) break;
        }
        try {
            parse_sample_store_bytes(span(b), "mem");
            ++accepted;
        } catch (const FormatError& e) {
            CHECK_THAT(e.what(), Catch::StartsWith("mem: "));
        }
    }
    CHECK(accepted < 30);  // the checksums catch (nearly) every mutation
}
