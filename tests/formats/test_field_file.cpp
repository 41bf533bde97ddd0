// The fitted-field file (.mlf, formats/field_file.hpp): round trips of every field kind evaluate
// bit-identically (values and gradients) to the built field; the bytes do not depend on the thread
// count; every defect class is refused with a one-line "PATH: offset N: ..." FormatError: wrong
// magic, other versions, every truncation, a flipped byte in every section, data of another set.
#include <catch2/catch.hpp>

#include <oneapi/tbb/global_control.h>

#include <bit>
#include <cmath>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "error_of.hpp"
#include "formats/binary_file.hpp"
#include "formats/crc32.hpp"
#include "formats/field_file.hpp"
#include "kernels/make_field.hpp"
#include "kernels/point_set_identity.hpp"
#include "kernels/splitmix.hpp"
#include "test_paths.hpp"

using namespace meshless;
using namespace meshless::test;

namespace {

/// n scattered points in [0,2]x[0,1]x[0,1.5] with a smooth value, some clustered (so octree leaves
/// grow and RBF-grid locals are grown/capped) and a few exact duplicates (merged).
PointSet scattered(std::size_t n, std::uint64_t seed) {
    PointSet ps;
    SplitMix r{seed};
    for (std::size_t i = 0; i < n; ++i) {
        Vec3 p{2 * r.unit(), r.unit(), 1.5 * r.unit()};
        if (i % 5 == 0) p = Vec3{0.3, 0.4, 0.5} + Vec3{0.05 * r.unit(), 0.05 * r.unit(), 0.05 * r.unit()};
        if (i % 97 == 1) p = ps.pos.back();
        ps.pos.push_back(p);
        ps.value.push_back(std::sin(3 * p.x) * std::cos(2 * p.y) + p.z * p.z);
    }
    ps.value_name = "f";
    ps.blocks.push_back({"points", {static_cast<std::int64_t>(n), 1, 1}, 0, n});
    return ps;
}

FittedData fitted(const PointSet& ps) {
    FittedData d;
    d.identity = point_set_identity(ps);
    d.value_name = ps.value_name;
    return d;
}

struct Built {
    std::unique_ptr<Field> field;
    FieldBuildStats stats;
};

Built build(const PointSet& ps, const FieldParams& p, int threads = 2) {
    oneapi::tbb::global_control limit(oneapi::tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
    Built b;
    b.field = make_field(ps, p, &b.stats);
    return b;
}

std::vector<Vec3> queries(std::size_t n, const std::array<Vec3, 2>& box) {
    SplitMix r{99};
    std::vector<Vec3> q(n);
    const Vec3 lo = box[0] - Vec3{0.2, 0.2, 0.2}, ext = box[1] - box[0] + Vec3{0.4, 0.4, 0.4};
    for (auto& p : q) p = lo + Vec3{ext.x * r.unit(), ext.y * r.unit(), ext.z * r.unit()};
    return q;
}

/// Value and gradient bits of `a` and `b` at every query, in one batch and one at a time.
void require_same_bits(const Field& a, const Field& b, std::span<const Vec3> q) {
    std::vector<double> va(q.size()), vb(q.size());
    std::vector<Vec3> ga(q.size()), gb(q.size());
    a.evaluate(q, va, ga);
    b.evaluate(q, vb, gb);
    std::size_t finite = 0;
    for (std::size_t i = 0; i < q.size(); ++i) {
        finite += std::isfinite(va[i]);
        REQUIRE(std::bit_cast<std::uint64_t>(va[i]) == std::bit_cast<std::uint64_t>(vb[i]));
        for (int k = 0; k < 3; ++k) REQUIRE(std::bit_cast<std::uint64_t>(ga[i][k]) == std::bit_cast<std::uint64_t>(gb[i][k]));
    }
    CHECK(finite > q.size() / 2);  // the comparison is not all-NaN
    for (std::size_t i = 0; i < q.size(); i += 997) {  // single points (no batch reordering)
        Vec3 g1, g2;
        REQUIRE(std::bit_cast<std::uint64_t>(a.value(q[i], &g1)) == std::bit_cast<std::uint64_t>(b.value(q[i], &g2)));
        REQUIRE(std::bit_cast<std::uint64_t>(g1.x) == std::bit_cast<std::uint64_t>(g2.x));
    }
}

std::vector<unsigned char> file_bytes(const std::string& path) {
    const auto b = read_file_bytes(path);
    std::vector<unsigned char> out(b.size());
    std::memcpy(out.data(), b.data(), b.size());
    return out;
}

FieldParams params_of(FieldKind k) {
    FieldParams p;
    p.kind = k;
    p.mpu_max_points = 30;  // a deeper octree on few points
    p.mpu_min_points = 12;
    return p;
}

}  // namespace

TEST_CASE("a .mlf round trip evaluates bit-identically to the built field, every kind, raw and compressed", "[formats][mlf]") {
    TempDir d("mlf_round");
    for (FieldKind k : {FieldKind::rbf_grid, FieldKind::mpu, FieldKind::global_rbf}) {
        const PointSet ps = scattered(k == FieldKind::global_rbf ? 400 : 4000, 7);
        FieldParams p = params_of(k);
        for (RbfGridSupport sup : {RbfGridSupport::neighbours27, RbfGridSupport::paper_radius}) {
            if (sup == RbfGridSupport::paper_radius && k != FieldKind::rbf_grid) continue;
            p.rbf_grid_support = sup;
            for (int level : {0, 1}) {
                INFO(field_kind_name(k) << " support " << int(sup) << " level " << level);
                const Built b = build(ps, p);
                const std::string path = (d / "f.mlf").string();
                write_field_file(path, *b.field, p, fitted(ps), b.stats, level);
                const FieldFile ff = read_field_file(path);
                REQUIRE(ff.field->name() == b.field->name());
                CHECK(ff.info.params.kind == k);
                CHECK(ff.info.params.rbf_grid_support == sup);
                CHECK(ff.info.data.identity.same_data(point_set_identity(ps)));
                CHECK(ff.info.data.value_name == "f");
                CHECK(ff.info.stats.locals == b.stats.locals);
                CHECK(ff.info.stats.merged_points == b.stats.merged_points);
                CHECK(ff.info.stats.merged_points > 0);
                for (int k = 0; k < 2; ++k) CHECK(norm(ff.field->bounds()[k] - b.field->bounds()[k]) == 0);
                require_same_bits(*b.field, *ff.field, queries(10000, ps.bounds()));
                // from memory too (the fuzz entry point)
                const FieldFile fm = parse_field_file_bytes(file_bytes(path), "mem");
                require_same_bits(*b.field, *fm.field, queries(2000, ps.bounds()));
            }
        }
    }
}

TEST_CASE("a .mlf keeps normalised axes and Hardy's c in world units", "[formats][mlf]") {
    TempDir d("mlf_norm");
    PointSet ps = scattered(3000, 11);
    for (auto& p : ps.pos) p.z *= 1000;  // an axis in other units
    for (FieldKind k : {FieldKind::rbf_grid, FieldKind::mpu}) {
        FieldParams p = params_of(k);
        p.normalise_axes = true;
        p.hardy_c_world = 0.03;
        const Built b = build(ps, p);
        write_field_file((d / "n.mlf").string(), *b.field, p, fitted(ps), b.stats);
        const FieldFile ff = read_field_file((d / "n.mlf").string());
        CHECK(ff.info.params.normalise_axes);
        CHECK(ff.info.params.hardy_c_world == 0.03);
        require_same_bits(*b.field, *ff.field, queries(10000, ps.bounds()));
    }
}

TEST_CASE("a .mlf does not depend on the thread count that fitted it", "[formats][mlf]") {
    TempDir d("mlf_threads");
    const PointSet ps = scattered(5000, 3);
    for (FieldKind k : {FieldKind::rbf_grid, FieldKind::mpu}) {
        const FieldParams p = params_of(k);
        const Built b1 = build(ps, p, 1), b2 = build(ps, p, 2);
        write_field_file((d / "t1.mlf").string(), *b1.field, p, fitted(ps), b1.stats);
        write_field_file((d / "t2.mlf").string(), *b2.field, p, fitted(ps), b2.stats);
        CHECK(file_bytes((d / "t1.mlf").string()) == file_bytes((d / "t2.mlf").string()));
    }
}

TEST_CASE("the data identity tells another point set apart", "[formats][mlf]") {
    const PointSet a = scattered(500, 5);
    PointSet b = a;
    CHECK(point_set_identity(a).same_data(point_set_identity(b)));
    b.value[123] = std::nextafter(b.value[123], 10.0);  // one bit of one value
    CHECK_FALSE(point_set_identity(a).same_data(point_set_identity(b)));
    b = a;
    std::swap(b.pos[3], b.pos[4]);  // the order
    std::swap(b.value[3], b.value[4]);
    CHECK_FALSE(point_set_identity(a).same_data(point_set_identity(b)));
    b = a;
    b.pos.pop_back();
    b.value.pop_back();
    CHECK_FALSE(point_set_identity(a).same_data(point_set_identity(b)));

    TempDir d("mlf_other");
    const FieldParams p = params_of(FieldKind::mpu);
    const Built bl = build(a, p);
    write_field_file((d / "a.mlf").string(), *bl.field, p, fitted(a), bl.stats);
    const FieldFile ff = read_field_file((d / "a.mlf").string());
    CHECK_NOTHROW(check_fitted_to(ff.info, point_set_identity(a), "a.mlf"));
    const std::string e = error_of([&] { check_fitted_to(ff.info, point_set_identity(b), "a.mlf"); });
    CHECK_THAT(e, Catch::StartsWith("a.mlf was fitted to other data: 500 points, hash "));
    CHECK_THAT(e, Catch::Contains("these are 499 points"));
}

namespace {

/// A small file of each kind (a few KB) for the must-fail cases.
std::vector<unsigned char> small_file(const TempDir& d, FieldKind k, int level) {
    const PointSet ps = scattered(k == FieldKind::global_rbf ? 40 : 300, 17);
    const FieldParams p = params_of(k);
    const Built b = build(ps, p);
    const std::string path = (d / "small.mlf").string();
    write_field_file(path, *b.field, p, fitted(ps), b.stats, level);
    return file_bytes(path);
}

std::string parse_error(const std::vector<unsigned char>& bytes) {
    return error_of([&] { parse_field_file_bytes(bytes, "bad.mlf"); });
}

void put_u32(std::vector<unsigned char>& b, std::size_t at, std::uint32_t v) { std::memcpy(b.data() + at, &v, 4); }
void fix_header_crc(std::vector<unsigned char>& b) { put_u32(b, 60, crc32_ieee(0, b.data(), 60)); }

/// Offsets of the section headers.
std::vector<std::size_t> section_offsets(const std::vector<unsigned char>& b) {
    std::vector<std::size_t> out;
    for (std::size_t at = kFieldFileHeaderBytes; at < b.size();) {
        out.push_back(at);
        std::uint64_t stored;
        std::memcpy(&stored, b.data() + at + 32, 8);
        at += kFieldFileSectionHeaderBytes + stored;
    }
    return out;
}

}  // namespace

TEST_CASE("a .mlf of another format version or with a wrong magic is refused", "[formats][mlf][mustfail]") {
    TempDir d("mlf_version");
    const auto good = small_file(d, FieldKind::mpu, 1);
    REQUIRE_NOTHROW(parse_field_file_bytes(good, "good.mlf"));
    auto b = good;
    put_u32(b, 8, kFieldFileVersion + 1);
    CHECK_THAT(parse_error(b), Catch::StartsWith("bad.mlf: offset 8: made by a newer version of meshless (format version 2"));
    put_u32(b, 8, 0);
    CHECK_THAT(parse_error(b), Catch::StartsWith("bad.mlf: offset 8: made by an older version of meshless"));
    fix_header_crc(b);  // a consistent header of another version still says so
    CHECK_THAT(parse_error(b), Catch::Contains("made by an older version"));
    b = good;
    b[1] = 'X';
    CHECK(parse_error(b) == "bad.mlf: offset 0: not a meshless field file (.mlf): wrong magic");
    // a PLY or an empty file is not a .mlf
    const std::string ply = "ply\nformat ascii 1.0\nend_header\n";
    CHECK_THAT(parse_error(std::vector<unsigned char>(ply.begin(), ply.end())), Catch::Contains("wrong magic"));
    CHECK_THAT(parse_error({}), Catch::StartsWith("bad.mlf: offset 0: truncated"));
}

TEST_CASE("every truncation of a .mlf is refused with the offset", "[formats][mlf][mustfail]") {
    TempDir d("mlf_trunc");
    for (FieldKind k : {FieldKind::rbf_grid, FieldKind::mpu, FieldKind::global_rbf}) {
        const auto good = small_file(d, k, 1);
        INFO(field_kind_name(k) << ", " << good.size() << " bytes");
        REQUIRE(good.size() < 400000);
        // Cuts: every one up to 4 KB and around every section boundary, then every 97th byte.
        std::vector<std::size_t> cuts;
        for (std::size_t c = 0; c < good.size(); ++c)
            if (c < 4096 || c % 97 == 0) cuts.push_back(c);
        for (std::size_t at : section_offsets(good))
            for (std::size_t c = at - std::min<std::size_t>(at, 2); c < std::min(good.size(), at + 50); ++c) cuts.push_back(c);
        for (std::size_t cut : cuts) {
            std::vector<unsigned char> b(good.begin(), good.begin() + static_cast<std::ptrdiff_t>(cut));
            std::string e = parse_error(b);
            if (e.rfind("bad.mlf: offset ", 0) != 0 || e.find('\n') != std::string::npos) FAIL("cut at " << cut << ": " << e);
            if (cut < kFieldFileHeaderBytes) continue;
            // the same cut behind a forged header that claims exactly the bytes left: found in the sections
            const std::uint64_t n = cut;
            std::memcpy(b.data() + 24, &n, 8);
            fix_header_crc(b);
            e = parse_error(b);
            if (e.rfind("bad.mlf: offset ", 0) != 0 || e.find('\n') != std::string::npos) FAIL("forged cut at " << cut << ": " << e);
        }
        // appended bytes
        auto b = good;
        b.push_back(0);
        CHECK_THAT(parse_error(b), Catch::Contains("bytes appended"));
    }
}

TEST_CASE("a flipped byte in any section of a .mlf is a checksum error naming the section", "[formats][mlf][mustfail]") {
    TempDir d("mlf_crc");
    for (int level : {0, 1})
        for (FieldKind k : {FieldKind::rbf_grid, FieldKind::mpu, FieldKind::global_rbf}) {
            const auto good = small_file(d, k, level);
            const auto offs = section_offsets(good);
            REQUIRE(offs.size() >= 8);
            // the header
            auto b = good;
            b[40] ^= 0x10;
            CHECK_THAT(parse_error(b), Catch::StartsWith("bad.mlf: offset 60: header checksum mismatch"));
            for (std::size_t s = 0; s < offs.size(); ++s) {
                const std::size_t at = offs[s];
                INFO(field_kind_name(k) << " level " << level << " section " << s);
                b = good;
                b[at + 20] ^= 0x01;  // its header (the flags)
                CHECK(parse_error(b) == "bad.mlf: offset " + std::to_string(at) + ": section header checksum mismatch (the file is damaged)");
                std::uint64_t stored;
                std::memcpy(&stored, good.data() + at + 32, 8);
                if (stored == 0) continue;
                b = good;
                b[at + kFieldFileSectionHeaderBytes + stored / 2] ^= 0x40;  // its payload
                CHECK_THAT(parse_error(b), Catch::StartsWith("bad.mlf: offset " + std::to_string(at + kFieldFileSectionHeaderBytes) + ": section '"));
                CHECK_THAT(parse_error(b), Catch::EndsWith("payload checksum mismatch (the file is damaged)"));
            }
        }
}

TEST_CASE("a .mlf with consistent checksums but inconsistent contents is refused", "[formats][mlf][mustfail]") {
    TempDir d("mlf_forged");
    const auto good = small_file(d, FieldKind::rbf_grid, 0);
    const auto offs = section_offsets(good);
    // rewrite one section header (and its CRC) the way a forger would
    auto forge = [&](std::size_t s, auto&& edit) {
        auto b = good;
        edit(b.data() + offs[s]);
        put_u32(b, offs[s] + 44, crc32_ieee(0, b.data() + offs[s], 44));
        return parse_error(b);
    };
    // an element count that claims more than the file holds (nothing may be allocated for it)
    CHECK_THAT(forge(5, [](unsigned char* h) { const std::uint64_t n = std::uint64_t{1} << 40; std::memcpy(h + 24, &n, 8); }),
               Catch::StartsWith("bad.mlf: offset " + std::to_string(offs[5] + 32)));
    CHECK_THAT(forge(5, [](unsigned char* h) { const std::uint64_t n = ~std::uint64_t{0}; std::memcpy(h + 24, &n, 8); }),
               Catch::Contains("too large"));
    CHECK_THAT(forge(5, [](unsigned char* h) { h[16] = 9; }), Catch::Contains("unknown element type 9"));
    CHECK_THAT(forge(5, [](unsigned char* h) { h[20] = 4; }), Catch::Contains("unknown flags"));
    CHECK_THAT(forge(5, [](unsigned char* h) { h[0] = 'Q'; }), Catch::Contains("bad section name byte"));
    CHECK_THAT(forge(0, [](unsigned char* h) { std::memcpy(h, "paramz", 6); }), Catch::Contains("expected 'params'"));
    // a section count that does not match
    auto b = good;
    put_u32(b, 20, static_cast<std::uint32_t>(offs.size() - 1));
    fix_header_crc(b);
    CHECK_THAT(parse_error(b), Catch::Contains("bytes after the last of"));
    put_u32(b, 20, 1000000);
    fix_header_crc(b);
    CHECK_THAT(parse_error(b), Catch::StartsWith("bad.mlf: offset 20: section count 1000000 does not fit the file"));
    // a compressed section whose payload decodes to more or fewer elements than its header declares
    {
        const auto z = small_file(d, FieldKind::rbf_grid, 1);
        const auto zoffs = section_offsets(z);
        std::size_t sec = 0;
        for (std::size_t k = 3; k < zoffs.size() && !sec; ++k) {
            std::uint32_t flags;
            std::memcpy(&flags, z.data() + zoffs[k] + 20, 4);
            if (flags & 1) sec = k;
        }
        REQUIRE(sec > 0);
        auto zforge = [&](std::int64_t delta) {
            auto b = z;
            std::uint64_t n;
            std::memcpy(&n, b.data() + zoffs[sec] + 24, 8);
            n = static_cast<std::uint64_t>(static_cast<std::int64_t>(n) + delta);
            std::memcpy(b.data() + zoffs[sec] + 24, &n, 8);
            put_u32(b, zoffs[sec] + 44, crc32_ieee(0, b.data() + zoffs[sec], 44));
            return parse_error(b);
        };
        CHECK_THAT(zforge(-1), Catch::Contains("payload decompresses to more than the declared"));
        CHECK_THAT(zforge(1), Catch::Contains("bytes, declared"));
        CHECK_THAT(zforge(std::int64_t{1} << 40), Catch::StartsWith("bad.mlf: offset " + std::to_string(zoffs[sec] + kFieldFileSectionHeaderBytes)));
    }
    // another field kind in the header than in the parameters
    b = good;
    put_u32(b, 16, 1);
    fix_header_crc(b);
    CHECK_THAT(parse_error(b), Catch::Contains("differs from the header's"));
}

TEST_CASE("a .mlf is written atomically and only to a regular file", "[formats][mlf]") {
    TempDir d("mlf_atomic");
    const PointSet ps = scattered(300, 1);
    const FieldParams p = params_of(FieldKind::rbf_grid);
    const Built b = build(ps, p);
    CHECK_THROWS_AS(write_field_file("-", *b.field, p, fitted(ps), b.stats), InvalidArgument);
    CHECK_THROWS_AS(write_field_file("/dev/null", *b.field, p, fitted(ps), b.stats), InvalidArgument);
    FieldParams other = p;
    other.kind = FieldKind::mpu;
    CHECK_THROWS_AS(write_field_file((d / "x.mlf").string(), *b.field, other, fitted(ps), b.stats), InvalidArgument);
    CHECK_THROWS_AS(write_field_file((d / "no/such/dir/x.mlf").string(), *b.field, p, fitted(ps), b.stats), IoError);
    for (const auto& e : std::filesystem::directory_iterator(d.path)) FAIL("left behind: " << e.path());
    CHECK(!is_field_file((d / "x.mlf").string()));
    write_field_file((d / "x.mlf").string(), *b.field, p, fitted(ps), b.stats);
    CHECK(is_field_file((d / "x.mlf").string()));
    CHECK_THAT(error_of<IoError>([&] { read_field_file((d / "missing.mlf").string()); }), Catch::Contains("missing.mlf"));
}
