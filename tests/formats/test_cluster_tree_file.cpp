// formats/cluster_tree_file (.mlh): round trip (bytes and nodes), and must-fail files per defect
// class: truncated, appended bytes, wrong magic, other versions, bad header/meta/node checksums,
// children out of range, cycles and shared children, counts that lie (children vs parent, root vs
// samples, splits, skipped, depth, error reached). The checksums are recomputed after each edit, so
// the structural checks themselves are exercised.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "formats/cluster_tree_file.hpp"
#include "formats/crc32.hpp"
#include "kernels/cluster_binary_tree.hpp"
#include "kernels/errors.hpp"
#include "test_paths.hpp"

using namespace meshless;
using namespace meshless::test;

namespace {

ClusterTree small_tree() {
    std::vector<Vec3> pos;
    std::vector<double> val;
    for (int k = 0; k < 6; ++k)
        for (int j = 0; j < 7; ++j)
            for (int i = 0; i < 8; ++i) {
                pos.push_back({i * 0.5, j * 1.0, k * 2.0});
                val.push_back(std::round(40 * std::sin(i * 0.7) + 10 * j - 3 * k));
            }
    CbtParams p;
    p.max_splits = 60;
    ClusterTree t = build_cluster_tree(pos, val, p);
    t.value_name = "density";
    return t;
}

template <class T>
void put_at(std::string& b, std::size_t at, T v) {
    std::memcpy(b.data() + at, &v, sizeof v);
}
template <class T>
T get_at(const std::string& b, std::size_t at) {
    T v;
    std::memcpy(&v, b.data() + at, sizeof v);
    return v;
}

/// Recomputes the checksums of an edited file: the header's always, the sections' where the
/// (possibly lying) header sizes keep them inside the bytes.
void fix_crcs(std::string& b) {
    const std::uint64_t meta = get_at<std::uint64_t>(b, 24), n = get_at<std::uint64_t>(b, 32);
    put_at<std::uint32_t>(b, 60, crc32_ieee(0, b.data(), 60));
    if (meta > b.size() || 64 + meta + 4 > b.size()) return;
    put_at<std::uint32_t>(b, 64 + meta, crc32_ieee(0, b.data() + 64, meta));
    const std::size_t at = 64 + meta + 4;
    if (n > (b.size() - at) / 56 || at + n * 56 + 4 > b.size()) return;
    put_at<std::uint32_t>(b, at + n * 56, crc32_ieee(0, b.data() + at, n * 56));
}

std::size_t node_at(const std::string& b, std::size_t i) { return 64 + get_at<std::uint64_t>(b, 24) + 4 + i * 56; }

/// The bytes of an older version of a version 4 file: without the samples' hash (3), and without
/// the certified table too (2: the table must be empty).
std::string older(const std::string& v4, std::uint32_t version) {
    REQUIRE(get_at<std::uint32_t>(v4, 8) == 4);
    const std::uint64_t meta = get_at<std::uint64_t>(v4, 24);
    const std::uint64_t cut = version == 2 ? 12 : 8;  // (u32 K = 0 and the hash; the hash)
    if (version == 2) REQUIRE(get_at<std::uint32_t>(v4, 64 + meta - 12) == 0);
    std::string b = v4.substr(0, 64 + meta - cut) + v4.substr(64 + meta);
    put_at<std::uint32_t>(b, 8, version);
    put_at<std::uint64_t>(b, 16, b.size());
    put_at<std::uint64_t>(b, 24, meta - cut);
    fix_crcs(b);
    return b;
}

std::string parse_error(const std::string& b) {
    try {
        (void)parse_cluster_tree_bytes(std::span<const unsigned char>(reinterpret_cast<const unsigned char*>(b.data()), b.size()), "t.mlh");
    } catch (const FormatError& e) {
        return e.what();
    }
    return "";
}

}  // namespace

TEST_CASE(".mlh round trip: same nodes, metadata and bytes", "[formats][cbt]") {
    TempDir d("mlh");
    const ClusterTree t = small_tree();
    const std::string path = (d / "t.mlh").string();
    write_cluster_tree_file(path, t);
    CHECK(is_cluster_tree_file(path));
    const ClusterTree r = read_cluster_tree_file(path);
    REQUIRE(r.nodes.size() == t.nodes.size());
    CHECK(std::memcmp(r.nodes.data(), t.nodes.data(), t.nodes.size() * sizeof(CbtNode)) == 0);
    CHECK(r.value_name == "density");
    CHECK(r.stats.splits == t.stats.splits);
    CHECK(r.stats.depth == t.stats.depth);
    CHECK(r.stats.error_reached == t.stats.error_reached);
    CHECK(r.stats.hardy_c_world == t.stats.hardy_c_world);
    CHECK(r.params.max_splits == 60);
    CHECK(r.bounds[1].z == 10);
    CHECK(cluster_tree_bytes(r) == cluster_tree_bytes(t));
    std::string disk(std::filesystem::file_size(path), '\0');
    std::FILE* f = std::fopen(path.c_str(), "rb");
    REQUIRE(std::fread(disk.data(), 1, disk.size(), f) == disk.size());
    std::fclose(f);
    CHECK(disk == cluster_tree_bytes(t));
    // no temporary left beside it
    int files = 0;
    for (const auto& e : std::filesystem::directory_iterator(d.path)) files += e.path().filename().string().find(".tmp") == std::string::npos ? 1 : 100;
    CHECK(files == 1);
    CHECK(parse_error(disk).empty());
}

TEST_CASE(".mlh version 1 (no split order, cluster value or size term) is read as max-error order and fits", "[formats][cbt]") {
    ClusterTree t = small_tree();
    t.params.order = CbtSplitOrder::max_error;
    t.params.value = CbtValueKind::fit;
    t.params.size_term = 0;
    const std::string v2 = older(cluster_tree_bytes(t), 2);
    // version 1: the same bytes without the 16 at meta offset 160 (order, value kind, size term)
    std::string v1 = v2.substr(0, 64 + 160) + v2.substr(64 + 176);
    put_at<std::uint32_t>(v1, 8, 1);
    put_at<std::uint64_t>(v1, 16, v1.size());
    put_at<std::uint64_t>(v1, 24, get_at<std::uint64_t>(v2, 24) - 16);
    fix_crcs(v1);
    const ClusterTree r = parse_cluster_tree_bytes(std::span<const unsigned char>(reinterpret_cast<const unsigned char*>(v1.data()), v1.size()), "v1.mlh");
    CHECK(r.params.order == CbtSplitOrder::max_error);
    CHECK(r.params.value == CbtValueKind::fit);
    CHECK(r.params.size_term == 0);
    CHECK(r.value_name == "density");
    CHECK(r.samples_hash == 0);  // (not recorded before version 4)
    CHECK(older(cluster_tree_bytes(r), 2) == v2);  // written again: the same tree
    // and the defaults round-trip as version 2
    const ClusterTree d = small_tree();
    const std::string b = cluster_tree_bytes(d);
    const ClusterTree rd = parse_cluster_tree_bytes(std::span<const unsigned char>(reinterpret_cast<const unsigned char*>(b.data()), b.size()), "d.mlh");
    CHECK(rd.params.order == CbtSplitOrder::weighted);
    CHECK(rd.params.value == CbtValueKind::mean);
    CHECK(rd.params.size_term == d.params.size_term);
}

TEST_CASE(".mlh must-fail files, one per defect class", "[formats][cbt]") {
    const std::string good = cluster_tree_bytes(small_tree());
    REQUIRE(parse_error(good).empty());
    const std::uint64_t n = get_at<std::uint64_t>(good, 32);
    auto expect = [&](std::string b, const std::string& what, bool fix = true) {
        if (fix) fix_crcs(b);
        const std::string e = parse_error(b);
        INFO(what << " -> '" << e << "'");
        CHECK_FALSE(e.empty());
        CHECK(e.find("t.mlh") == 0);
        CHECK(e.find('\n') == std::string::npos);
        CHECK(e.find(what) != std::string::npos);
    };
    SECTION("truncated and appended") {
        for (std::size_t keep : {std::size_t{0}, std::size_t{5}, std::size_t{40}, std::size_t{64}, good.size() / 2, good.size() - 1})
            CHECK_FALSE(parse_error(good.substr(0, keep)).empty());
        expect(good.substr(0, good.size() - 56), "truncated", false);
        expect(good + "x", "after the declared end", false);
    }
    SECTION("magic and version") {
        std::string b = good;
        b[1] = 'X';
        expect(b, "magic", false);
        b = good;
        put_at<std::uint32_t>(b, 8, 5);
        expect(b, "newer version");
        put_at<std::uint32_t>(b, 8, 0);
        expect(b, "older version");
    }
    SECTION("checksums") {
        std::string b = good;
        b[20] ^= 1;
        expect(b, "header checksum", false);
        b = good;
        b[64 + 3] ^= 1;
        expect(b, "meta checksum", false);
        b = good;
        b[node_at(good, 1) + 2] ^= 1;
        expect(b, "node checksum", false);
    }
    SECTION("header sizes that lie") {
        std::string b = good;
        put_at<std::uint64_t>(b, 32, n + 2);
        expect(b, "nodes do not fill");
        put_at<std::uint64_t>(b, 32, std::uint64_t{1} << 62);
        expect(b, "nodes do not fill");
        b = good;
        put_at<std::uint64_t>(b, 24, 10);
        expect(b, "meta size");
        b = good;
        b[45] = 1;
        expect(b, "padding");
    }
    SECTION("children out of range, cycles, shared children") {
        std::string b = good;
        put_at<std::uint32_t>(b, node_at(good, 0) + 48, static_cast<std::uint32_t>(n));
        expect(b, "out of range");
        b = good;
        put_at<std::uint32_t>(b, node_at(good, 0) + 48, 0);  // the root's first child is itself: a leaf root in a bigger tree
        expect(b, "node");
        // a later node pointing back to an earlier one (a cycle)
        std::size_t internal = 0;
        for (std::size_t i = 1; i < n; ++i)
            if (get_at<std::uint32_t>(good, node_at(good, i) + 48) != 0) internal = i;
        REQUIRE(internal > 0);
        b = good;
        put_at<std::uint32_t>(b, node_at(good, internal) + 48, 1);
        expect(b, "node");
        // two parents sharing children
        b = good;
        const std::uint32_t rc = get_at<std::uint32_t>(good, node_at(good, 0) + 48);
        put_at<std::uint32_t>(b, node_at(good, internal) + 48, rc);
        expect(b, "node");
    }
    SECTION("counts that lie") {
        std::string b = good;
        put_at<std::uint32_t>(b, node_at(good, 1) + 40, get_at<std::uint32_t>(good, node_at(good, 1) + 40) + 1);
        expect(b, "samples");
        b = good;
        put_at<std::uint64_t>(b, 64, get_at<std::uint64_t>(good, 64) + 1);
        expect(b, "samples");
        b = good;
        put_at<std::uint64_t>(b, 64 + 16, get_at<std::uint64_t>(good, 64 + 16) + 1);
        expect(b, "splits");
        b = good;
        put_at<std::uint64_t>(b, 64 + 24, 5);
        expect(b, "skipped");
        b = good;
        put_at<std::uint32_t>(b, 64 + 32, 99);
        expect(b, "depth");
        b = good;
        put_at<double>(b, 64 + 88, 1e9);
        expect(b, "error reached");
        b = good;
        put_at<std::uint32_t>(b, node_at(good, 2) + 44, 7);
        expect(b, "depth");
        b = good;
        put_at<double>(b, node_at(good, 2) + 32, -1.0);
        expect(b, "error");
        b = good;
        put_at<double>(b, node_at(good, 2) + 24, std::nan(""));
        expect(b, "value");
        b = good;
        put_at<std::uint32_t>(b, node_at(good, 2) + 52, 4);
        expect(b, "flags");
        b = good;
        put_at<std::uint32_t>(b, 64 + 176, 5000);  // beyond the meta
        expect(b, "name of");
        b = good;
        put_at<std::uint32_t>(b, 64 + 160, 2);
        expect(b, "split order");
        b = good;
        put_at<std::uint32_t>(b, 64 + 164, 7);
        expect(b, "cluster value");
        b = good;
        put_at<double>(b, 64 + 168, -0.5);
        expect(b, "size term");
        b = good;
        put_at<double>(b, 64 + 168, std::nan(""));
        expect(b, "size term");
        b = good;
        put_at<std::uint32_t>(b, 64 + 44, 9);
        expect(b, "scaling");
    }
}

TEST_CASE(".mlh writing refuses streams and leaves nothing on failure", "[formats][cbt]") {
    const ClusterTree t = small_tree();
    CHECK_THROWS_AS(write_cluster_tree_file("-", t), InvalidArgument);
    CHECK_THROWS_AS(write_cluster_tree_file("/nonexistent-dir/x.mlh", t), IoError);
    CHECK_FALSE(is_cluster_tree_file("/nonexistent-dir/x.mlh"));
}

namespace {

/// small_tree with three certified errors.
ClusterTree certified_tree() {
    ClusterTree t = small_tree();
    t.certified = {{1, INFINITY, 0.025}, {10, 12.5, 0.025}, {61, 0.25, 0.003}};
    return t;
}

/// Where the certified table starts in a file of certified_tree(): after the header, the fixed meta and the name.
constexpr std::size_t kTableAt = 64 + kClusterTreeMetaFixedBytes + 7;  // "density"

}  // namespace

TEST_CASE(".mlh version 4: certified errors and the samples' hash round trip, versions 2 and 3 still read", "[formats][cbt]") {
    const ClusterTree t = certified_tree();
    REQUIRE(t.samples_hash != 0);
    const std::string b = cluster_tree_bytes(t);
    CHECK(get_at<std::uint32_t>(b, 8) == 4);
    CHECK(get_at<std::uint64_t>(b, 24) == kClusterTreeMetaFixedBytes + 7 + 4 + 3 * kClusterTreeCertifiedBytes + 8);
    const std::string plain = cluster_tree_bytes(small_tree());
    CHECK(get_at<std::uint32_t>(plain, 8) == 4);
    CHECK(get_at<std::uint64_t>(plain, 24) == kClusterTreeMetaFixedBytes + 7 + 4 + 8);
    const auto parse = [](const std::string& bytes) {
        return parse_cluster_tree_bytes(std::span<const unsigned char>(reinterpret_cast<const unsigned char*>(bytes.data()), bytes.size()), "t.mlh");
    };
    const ClusterTree r = parse(b);
    REQUIRE(r.certified.size() == 3);
    for (std::size_t i = 0; i < 3; ++i) {
        CHECK(r.certified[i].count == t.certified[i].count);
        CHECK(r.certified[i].max_error == t.certified[i].max_error);
        CHECK(r.certified[i].hardy_c_rel == t.certified[i].hardy_c_rel);
    }
    CHECK(r.samples_hash == t.samples_hash);
    CHECK(r.value_name == "density");
    CHECK(cluster_tree_bytes(r) == b);
    // the files of versions 3 and 2 read as before, with no hash
    const ClusterTree r3 = parse(older(b, 3));
    CHECK(r3.certified.size() == 3);
    CHECK(r3.samples_hash == 0);
    CHECK(parse(older(plain, 2)).samples_hash == 0);
    TempDir d("mlh4");
    write_cluster_tree_file((d / "t.mlh").string(), t);
    std::ifstream in(d / "t.mlh", std::ios::binary);
    CHECK(std::string(std::istreambuf_iterator<char>(in), {}) == b);
    CHECK(cluster_tree_file_version((d / "t.mlh").string()) == 4);
    ClusterTree many = small_tree();
    for (std::uint64_t k = 1; k <= kMaxCertifiedErrors + 1; ++k) many.certified.push_back({k, 1, 0.025});
    CHECK_THROWS_AS(cluster_tree_bytes(many), InvalidArgument);
}

TEST_CASE(".mlh version 3 and 4 must-fail files: the certified table's defects, the hash's room", "[formats][cbt]") {
    const std::string good = cluster_tree_bytes(certified_tree());
    REQUIRE(parse_error(good).empty());
    auto expect = [&](std::string b, const std::string& what) {
        fix_crcs(b);
        const std::string e = parse_error(b);
        INFO(what << " -> '" << e << "'");
        CHECK(e.find("t.mlh: offset ") == 0);
        CHECK(e.find('\n') == std::string::npos);
        CHECK(e.find(what) != std::string::npos);
    };
    const std::size_t entry = kTableAt + 4;  // the first entry
    std::string b = good;
    put_at<std::uint32_t>(b, kTableAt, 4);  // one more than the bytes hold
    expect(b, "do not fill");
    put_at<std::uint32_t>(b, kTableAt, 65);
    expect(b, "at most 64");
    b = good;
    put_at<std::uint64_t>(b, entry, 0);
    expect(b, "count 0 outside 1..61");
    b = good;
    put_at<std::uint64_t>(b, entry + 2 * 24, 62);  // beyond the leaves
    expect(b, "count 62 outside 1..61");
    b = good;
    put_at<std::uint64_t>(b, entry + 24, 1);  // equal to the one before
    expect(b, "not ascending");
    b = good;
    put_at<double>(b, entry + 24 + 8, -1.0);
    expect(b, "negative or NaN");
    put_at<double>(b, entry + 24 + 8, NAN);
    expect(b, "negative or NaN");
    b = good;
    put_at<double>(b, entry + 16, 0.0);
    expect(b, "Hardy c outside");
    put_at<double>(b, entry + 16, INFINITY);
    expect(b, "Hardy c outside");
    // a name that claims the table's and the hash's bytes
    b = good;
    put_at<std::uint32_t>(b, kTableAt - 7 - 4, 7 + 4 + 3 * 24 + 8 + 1);
    expect(b, "name of");
    // a version 2 file with the table's bytes: its name does not fill the meta
    b = good;
    put_at<std::uint32_t>(b, 8, 2);
    expect(b, "name of");
    // a version 3 file without the table
    b = good.substr(0, kTableAt) + good.substr(kTableAt + 4 + 3 * 24 + 8);
    put_at<std::uint32_t>(b, 8, 3);
    put_at<std::uint64_t>(b, 24, kClusterTreeMetaFixedBytes + 7);
    put_at<std::uint64_t>(b, 16, b.size());
    expect(b, "without its certified error count");
    // a version 4 file without the hash: the table does not fill what is left
    b = good.substr(0, kTableAt + 4 + 3 * 24) + good.substr(kTableAt + 4 + 3 * 24 + 8);
    put_at<std::uint64_t>(b, 24, kClusterTreeMetaFixedBytes + 7 + 4 + 3 * 24);
    put_at<std::uint64_t>(b, 16, b.size());
    expect(b, "do not fill");
    // a version 4 file with neither
    b = good.substr(0, kTableAt) + good.substr(kTableAt + 4 + 3 * 24 + 8);
    put_at<std::uint64_t>(b, 24, kClusterTreeMetaFixedBytes + 7);
    put_at<std::uint64_t>(b, 16, b.size());
    expect(b, "without its certified error count and samples hash");
}
