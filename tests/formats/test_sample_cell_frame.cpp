// formats/sample_cell_frame: cell-indexed sample frames. Oracles: the records sample_active_cells
// generates (every sample type, odd grids, offsets, negative spacing, indices past 65,535) come back
// byte for byte; the generator's promise behind Verify::position (value and gradient are the
// corners') is checked by Verify::all finding no exception; records of another producer become
// exceptions and still round-trip; the stream writer picks the frame and the reader gives the same
// records; every defect class of a payload is refused.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "formats/crc32.hpp"
#include "formats/point_stream.hpp"
#include "formats/sample_cell_frame.hpp"
#include "kernels/cell_sampling.hpp"
#include "tests/error_of.hpp"

using namespace meshless;
using Catch::Matchers::Contains;
using meshless::test::error_of;

namespace {

using Verify = SampleCellEncoder::Verify;

bool same_records(const std::vector<SampleRecord>& a, const std::vector<SampleRecord>& b) {
    return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(SampleRecord)) == 0);
}

/// The samples of a random volume of type T at a middle isovalue.
template <class T>
std::vector<SampleRecord> samples_of(GridSpec g, std::uint32_t seed, SamplingParams sp = {}) {
    std::mt19937 rng(seed);
    std::vector<T> v(static_cast<std::size_t>(g.voxel_count()));
    double iso = 0.5;
    if constexpr (std::is_floating_point_v<T>) {
        std::uniform_real_distribution<float> d(-1.0f, 1.0f);
        for (auto& x : v) x = d(rng);
        iso = 0.1;
    } else {
        std::uniform_int_distribution<int> d(std::numeric_limits<T>::min(), std::numeric_limits<T>::max());
        for (auto& x : v) x = static_cast<T>(d(rng));
        iso = (double(std::numeric_limits<T>::min()) + double(std::numeric_limits<T>::max())) / 2 + 0.5;
    }
    const SampleType type = std::is_same_v<T, std::uint8_t>    ? SampleType::u8
                            : std::is_same_v<T, std::int16_t>  ? SampleType::i16
                            : std::is_same_v<T, std::uint16_t> ? SampleType::u16
                                                               : SampleType::f32;
    std::vector<SampleRecord> out;
    SamplingStats st;
    sample_active_cells(VolumeView{v.data(), type, g}, iso, 0, cell_row_count(g), sp, out, st);
    return out;
}

GridSpec grid(std::int64_t nx, std::int64_t ny, std::int64_t nz, std::array<double, 3> origin, std::array<double, 3> spacing) {
    GridSpec g;
    g.dims = {nx, ny, nz};
    g.origin = origin;
    g.spacing = spacing;
    return g;
}

CellGrid cells_of(const GridSpec& g) { return cell_grid(g); }

/// Encodes (must compact), decodes, and returns the decoded records and the payload.
std::vector<SampleRecord> round_trip(const std::vector<SampleRecord>& rec, const CellGrid& g, Verify verify,
                                     std::vector<char>* payload_out = nullptr) {
    SampleCellEncoder enc(g, verify);
    std::vector<char> payload;
    REQUIRE(enc.encode(rec.data(), rec.size(), payload));
    std::vector<SampleRecord> back(rec.size());
    SampleCellDecoder dec;
    dec.decode(payload.data(), payload.size(), rec.size(), back.data());
    if (payload_out) *payload_out = payload;
    return back;
}

/// Recomputes a record's fields from its corners, as the generator would for those corners.
void rebuild(SampleRecord& s, const CellGrid& g) {
    std::uint32_t ijk[3];
    for (int a = 0; a < 3; ++a) ijk[a] = static_cast<std::uint32_t>(std::lround((double(s.cell_lo[a]) - g.origin[a]) / g.spacing[a]));
    complete_centre_samples(g.origin, g.spacing, ijk, &s, 1);
}

std::uint32_t exceptions_of(const std::vector<char>& payload) {
    std::uint32_t e;
    std::memcpy(&e, payload.data() + 4, 4);
    return e;
}

}  // namespace

TEST_CASE("generated samples of every type come back byte for byte, in the narrowest coding", "[sample-cells]") {
    const GridSpec g = grid(37, 23, 11, {-3.25, 17.0, 1e3}, {0.7, 1.3, 0.25});
    const CellGrid cg = cells_of(g);
    struct Case {
        const char* name;
        std::vector<SampleRecord> rec;
        std::size_t slot;
    };
    const Case cases[] = {{"uint8", samples_of<std::uint8_t>(g, 1), 6 + 8},
                          {"int16", samples_of<std::int16_t>(g, 2), 6 + 16},
                          {"uint16", samples_of<std::uint16_t>(g, 3), 6 + 16},
                          {"float32", samples_of<float>(g, 4), 6 + 32}};
    for (const Case& c : cases) {
        INFO(c.name);
        REQUIRE(c.rec.size() > 500);
        for (Verify v : {Verify::position, Verify::all}) {
            std::vector<char> payload;
            CHECK(same_records(round_trip(c.rec, cg, v, &payload), c.rec));
            // the generator's promise: every record rebuilds exactly from its cell (no exception)
            CHECK(exceptions_of(payload) == 0);
            CHECK(payload.size() == kSampleCellHeaderBytes + c.rec.size() * c.slot);
        }
    }
}

TEST_CASE("the uint8 integer path gives complete_centre_samples' bytes", "[sample-cells]") {
    // corners over the whole uint8 range, including the extreme gradients (+-1020 / 4)
    std::mt19937 rng(7);
    std::uniform_int_distribution<int> d(0, 255);
    const double origin[3] = {-1.5, 0.0, 2e5}, spacing[3] = {0.703125, -1.25, 3.0e-3};
    const std::size_t n = 2001;  // odd: the last record takes the scalar tail
    std::vector<std::uint32_t> ijk(3 * n);
    std::vector<std::uint8_t> corners(8 * n);
    for (std::size_t r = 0; r < n; ++r) {
        for (int a = 0; a < 3; ++a) ijk[3 * r + a] = static_cast<std::uint32_t>(r / 7 + 70000 * a);
        for (int q = 0; q < 8; ++q) corners[8 * r + q] = static_cast<std::uint8_t>(r < 16 ? ((q & 1) ^ (r & 1) ? 255 : 0) : d(rng));
    }
    std::vector<SampleRecord> a(n), b(n);
    for (std::size_t r = 0; r < n; ++r)
        for (int q = 0; q < 8; ++q) a[r].corner[q] = static_cast<float>(corners[8 * r + q]);
    complete_centre_samples(origin, spacing, ijk.data(), a.data(), n);
    CentreGradientTable table;
    complete_centre_samples_u8(origin, spacing, ijk.data(), corners.data(), b.data(), n, table);
    CHECK(same_records(a, b));
    // the two-records-per-step path against one record per call (the scalar definition), odd n
    std::vector<SampleRecord> one = a;
    for (std::size_t r = 0; r < n; ++r) complete_centre_samples(origin, spacing, ijk.data() + 3 * r, &one[r], 1);
    CHECK(same_records(a, one));
    // a table keyed by +0 spacing is not reused for -0 (opposite infinite gradients)
    const double pz[3] = {0.0, 1.0, 1.0}, nz[3] = {-0.0, 1.0, 1.0};
    complete_centre_samples(nz, nz, ijk.data(), a.data(), n);
    complete_centre_samples_u8(pz, pz, ijk.data(), corners.data(), b.data(), n, table);
    complete_centre_samples_u8(nz, nz, ijk.data(), corners.data(), b.data(), n, table);
    CHECK(same_records(a, b));
    // a table made for another spacing is remade
    const double other[3] = {1.0, 2.0, 4.0};
    complete_centre_samples(other, other, ijk.data(), a.data(), n);
    complete_centre_samples_u8(other, other, ijk.data(), corners.data(), b.data(), n, table);
    CHECK(same_records(a, b));
}

TEST_CASE("bricked sampling, negative spacing and indices past 65535 round-trip", "[sample-cells]") {
    SECTION("index offset (a brick of a larger volume)") {
        SamplingParams sp;
        sp.index_offset = {70000, 3, 123456};
        const GridSpec g = grid(19, 9, 6, {0.0, 0.0, 0.0}, {0.5, 0.5, 2.0});
        const auto rec = samples_of<std::uint8_t>(g, 11, sp);
        std::vector<char> payload;
        CHECK(same_records(round_trip(rec, cells_of(g), Verify::position, &payload), rec));
        CHECK(payload[1] == 4);  // 4-byte indices
        CHECK(exceptions_of(payload) == 0);
    }
    SECTION("negative spacing") {
        const GridSpec g = grid(15, 12, 7, {10.0, -4.0, 3.0}, {-0.75, 1.0, -2.5});
        const auto rec = samples_of<std::int16_t>(g, 12);
        std::vector<char> payload;
        CHECK(same_records(round_trip(rec, cells_of(g), Verify::position, &payload), rec));
        CHECK(exceptions_of(payload) == 0);
    }
}

TEST_CASE("records of another producer become exceptions and still round-trip", "[sample-cells]") {
    const GridSpec g = grid(30, 20, 9, {1.0, 2.0, 3.0}, {0.5, 0.25, 1.0});
    auto rec = samples_of<std::uint8_t>(g, 21);
    REQUIRE(rec.size() > 300);
    rec[3].value += 0.25f;                             // not the corners' value: only Verify::all sees it
    rec[10].radius *= 2;                               // another radius
    rec[20].cell_lo[1] += 0.1f;                        // off the grid
    rec[30].pos[0] = std::numeric_limits<float>::quiet_NaN();
    rec[40].cell_lo[2] = -1e30f;                       // no index at all
    rec[50].corner[5] = 0.5f;                          // a corner no integer coding holds, rebuilt
    rebuild(rec[50], cells_of(g));
    rec[60].grad[2] = -rec[60].grad[2] + 1.0f;
    std::vector<char> payload;
    CHECK(same_records(round_trip(rec, cells_of(g), Verify::all, &payload), rec));
    CHECK(exceptions_of(payload) == 6);                // every record but rec[50] (its corners fit float32)
    CHECK(payload[0] == 4);                            // float32 corners: rec[50] is exact
    // Verify::position trusts value and gradient: those two come back as the corners give them
    const auto back = round_trip(rec, cells_of(g), Verify::position, &payload);
    CHECK(exceptions_of(payload) == 4);
    CHECK(back[3].value != rec[3].value);
    CHECK(std::memcmp(&back[10], &rec[10], sizeof(SampleRecord)) == 0);
}

TEST_CASE("corner codings widen across frames and never lose a value", "[sample-cells]") {
    const GridSpec g = grid(12, 10, 5, {0, 0, 0}, {1, 1, 1});
    auto a = samples_of<std::uint8_t>(g, 31);
    auto b = a, c = a, d = a;
    b[5].corner[2] = -7.0f;   // needs int16
    c[7].corner[0] = 60000;   // needs uint16
    d[9].corner[1] = -0.0f;   // -0 is no integer's float: float32
    rebuild(b[5], cells_of(g));
    rebuild(c[7], cells_of(g));
    rebuild(d[9], cells_of(g));
    SampleCellEncoder enc(cells_of(g), Verify::all);
    SampleCellDecoder dec;
    const int coding[] = {1, 2, 3, 4, 4};  // up the ladder, never down
    int f = 0;
    for (const auto* frame : {&a, &b, &c, &d, &a}) {
        std::vector<char> payload;
        REQUIRE(enc.encode(frame->data(), frame->size(), payload));
        CHECK(payload[0] == coding[f++]);
        CHECK(exceptions_of(payload) == 0);
        std::vector<SampleRecord> back(frame->size());
        dec.decode(payload.data(), payload.size(), frame->size(), back.data());
        CHECK(same_records(back, *frame));
    }
}

TEST_CASE("frames too small to gain are left raw", "[sample-cells]") {
    const GridSpec g = grid(12, 10, 5, {0, 0, 0}, {1, 1, 1});
    const auto rec = samples_of<std::uint8_t>(g, 41);
    SampleCellEncoder enc(cells_of(g), Verify::position);
    std::vector<char> payload;
    CHECK_FALSE(enc.encode(rec.data(), 0, payload));
    CHECK_FALSE(enc.encode(rec.data(), 1, payload));  // 64 + 14 bytes > 44
    CHECK(enc.encode(rec.data(), 4, payload));        // 64 + 56 <= 176
    // records none of which rebuild (another grid) are not worth a frame of exceptions
    SampleCellEncoder other(CellGrid{{0.3, 0, 0}, {1, 1, 1}}, Verify::all);
    CHECK_FALSE(other.encode(rec.data(), rec.size(), payload));
}

TEST_CASE("every defect of a cell-indexed payload is refused", "[sample-cells]") {
    const GridSpec g = grid(12, 10, 5, {0, 0, 0}, {1, 1, 1});
    auto rec = samples_of<std::uint8_t>(g, 51);
    rec[2].value = 1e6f;  // one exception
    SampleCellEncoder enc(cells_of(g), Verify::all);
    std::vector<char> good;
    REQUIRE(enc.encode(rec.data(), rec.size(), good));
    REQUIRE(exceptions_of(good) == 1);
    const std::uint64_t n = rec.size();
    auto fails = [&](std::vector<char> p, std::uint64_t count, const char* what) {
        std::vector<SampleRecord> out(static_cast<std::size_t>(std::min<std::uint64_t>(count, n + 10)));
        SampleCellDecoder dec;
        INFO(what);
        CHECK_THAT(error_of([&] { dec.decode(p.data(), p.size(), count, out.data()); }), Contains(what));
    };
    auto with = [&](std::size_t at, const void* bytes, std::size_t len) {
        std::vector<char> p = good;
        std::memcpy(p.data() + at, bytes, len);
        return p;
    };
    const std::uint8_t five = 5, zero8 = 0, three = 3, one = 1;
    const double inf = std::numeric_limits<double>::infinity();
    const std::uint32_t big = static_cast<std::uint32_t>(n + 1), last = static_cast<std::uint32_t>(n);
    fails(std::vector<char>(good.begin(), good.begin() + 40), 0, "shorter than its header");
    fails(with(0, &five, 1), n, "unknown corner coding 5");
    fails(with(0, &zero8, 1), n, "unknown corner coding 0");
    fails(with(1, &three, 1), n, "index width 3");
    fails(with(2, &one, 1), n, "reserved header bytes");
    fails(with(13, &one, 1), n, "reserved header bytes");
    fails(with(16, &inf, 8), n, "not finite");
    fails(with(48 + 8, &inf, 8), n, "not finite");
    fails(with(4, &big, 4), n, "exceptions for");
    fails(good, n + 1, "the header implies");
    fails(good, n - 1, "the header implies");
    fails(std::vector<char>(good.begin(), good.end() - 1), n, "the header implies");
    // the exception's record number: past the end
    const std::size_t exc = good.size() - (4 + sizeof(SampleRecord));
    fails(with(exc, &last, 4), n, "names record");
    // two exceptions out of order
    {
        auto rec2 = rec;
        rec2[8].value = 1e6f;
        std::vector<char> p;
        REQUIRE(enc.encode(rec2.data(), rec2.size(), p));
        REQUIRE(exceptions_of(p) == 2);
        const std::uint32_t first = 8, second = 2;
        const std::size_t e0 = p.size() - 2 * (4 + sizeof(SampleRecord)), e1 = e0 + 4 + sizeof(SampleRecord);
        std::memcpy(p.data() + e0, &first, 4);
        std::memcpy(p.data() + e1, &second, 4);
        fails(p, n, "out of order");
        std::memcpy(p.data() + e1, &first, 4);  // the same record twice
        fails(p, n, "out of order");
    }
}

namespace {

std::string sample_stream(const std::vector<SampleRecord>& rec, const CellGrid* cells, bool compress = false) {
    char* buf = nullptr;
    std::size_t len = 0;
    std::FILE* f = open_memstream(&buf, &len);
    {
        StreamWriter w(f, "mem", RecordKind::sample, compress);
        if (cells) w.index_cells(*cells, Verify::position);
        w.write_meta({});
        const std::size_t half = rec.size() / 2;
        w.write_data(0, rec.data(), half);
        w.write_data(1, rec.data() + half, rec.size() - half);
        w.finish();
    }
    std::fclose(f);
    std::string s(buf, len);
    std::free(buf);
    return s;
}

std::vector<SampleRecord> read_samples(const std::string& bytes) {
    std::FILE* f = fmemopen(const_cast<char*>(bytes.data()), bytes.size(), "rb");
    std::vector<char> raw;
    try {
        StreamReader r(f, "mem");
        while (r.next_data(raw)) {
        }
    } catch (...) {
        std::fclose(f);
        throw;
    }
    std::fclose(f);
    std::vector<SampleRecord> out(raw.size() / sizeof(SampleRecord));
    if (!out.empty()) std::memcpy(out.data(), raw.data(), raw.size());
    return out;
}

/// Offset of the first DATA frame's header in a stream written by sample_stream (after the
/// 32-byte stream header and the META frame of an empty StreamMeta: 32 bytes).
constexpr std::size_t kFirstData = 64;

void patch_frame_flags(std::string& s, std::uint32_t flags) { std::memcpy(s.data() + kFirstData + 4, &flags, 4); }

}  // namespace

TEST_CASE("a sample stream written cell-indexed reads back the same records in a sixth of the bytes", "[sample-cells]") {
    const GridSpec g = grid(40, 30, 12, {0.5, -2.0, 7.0}, {0.703125, 0.703125, 1.25});
    const auto rec = samples_of<std::uint8_t>(g, 61);
    const CellGrid cg = cells_of(g);
    const std::string raw = sample_stream(rec, nullptr), cells = sample_stream(rec, &cg);
    CHECK(same_records(read_samples(raw), rec));
    CHECK(same_records(read_samples(cells), rec));
    CHECK(cells.size() * 5 < raw.size());
    // compression keeps raw records (zstd frames): no cell indexing
    const std::string z = sample_stream(rec, &cg, true);
    CHECK(same_records(read_samples(z), rec));
    // a flipped payload bit is a checksum error like any frame's
    std::string bad = cells;
    bad[kFirstData + 32 + 70] ^= 4;
    CHECK_THAT(error_of([&] { read_samples(bad); }), Contains("checksum mismatch"));
}

TEST_CASE("cell-indexed frames: flags and kinds they may not have are refused", "[sample-cells]") {
    const GridSpec g = grid(40, 30, 12, {0, 0, 0}, {1, 1, 1});
    const auto rec = samples_of<std::uint8_t>(g, 71);
    const CellGrid cg = cells_of(g);
    std::string s = sample_stream(rec, &cg);
    std::uint32_t flags;
    std::memcpy(&flags, s.data() + kFirstData + 4, 4);
    REQUIRE(flags == 2);
    {
        std::string t = s;
        patch_frame_flags(t, 3);
        CHECK_THAT(error_of([&] { read_samples(t); }), Contains("flagged both zstd and cell-indexed"));
        patch_frame_flags(t, 6);
        CHECK_THAT(error_of([&] { read_samples(t); }), Contains("unknown flags 0x6"));
    }
    {
        std::string t = s;  // the same frames in a stream that says it holds points
        const std::uint32_t point = 1, size = 32;
        std::memcpy(t.data() + 12, &point, 4);
        std::memcpy(t.data() + 16, &size, 4);
        CHECK_THAT(error_of([&] { read_samples(t); }), Contains("cell-indexed DATA frame in a stream of kind 1"));
    }
    {
        // a frame header claiming more records than its payload holds (the count is outside the
        // checksum): refused by the payload's size (and read_samples' memory stays small: a room of
        // 8 M records would be 738 MB)
        std::string t = s;
        const std::uint64_t huge = std::uint64_t{1} << 23;
        std::memcpy(t.data() + kFirstData + 16, &huge, 8);
        CHECK_THAT(error_of([&] { read_samples(t); }), Contains("cell-indexed sample frame of 8388608 records has"));
    }
    {
        std::string t = s;  // a damaged coding byte behind a valid checksum names the stream
        std::uint32_t bytes;
        std::memcpy(&bytes, t.data() + kFirstData + 24, 4);
        t[kFirstData + 32] = 9;
        const std::uint32_t crc = crc32_ieee(0, t.data() + kFirstData + 32, bytes);
        std::memcpy(t.data() + kFirstData + 28, &crc, 4);
        CHECK_THAT(error_of([&] { read_samples(t); }), Contains("mem: cell-indexed sample frame: unknown corner coding 9"));
    }
}
