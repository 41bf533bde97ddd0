// meshless hierarchy / lod / info on .mlh files from the command line: the tree file does not
// depend on --threads, lod writes the LOD the library traverses (and warns, giving the finest,
// beyond the tree), point-set commands read a .mlh LOD (--lod-level/--lod-error) as they read the
// same points from a file, and bad input gets a one-line error and a non-zero exit with nothing
// written.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>
#include <utility>
#include <vector>

#include "cli/cli_harness.hpp"
#include "formats/cluster_tree_file.hpp"
#include "formats/point_set_reader.hpp"
#include "kernels/cluster_lod.hpp"
#include "kernels/field_params.hpp"
#include "kernels/make_field.hpp"

using namespace meshless;
using namespace meshless::test;

namespace {

bool one_line(const std::string& err) { return !err.empty() && err.find('\n') == err.size() - 1; }

std::string write_csv(const TempDir& d, const std::string& name, const std::string& rows) {
    const auto p = d / name;
    spit(p, "x,y,z,value\n" + rows);
    return p.string();
}

/// The (x, value) of each data row of a CSV that lod wrote (x,y,z,value after a header line).
std::vector<std::pair<double, double>> csv_x_and_value(const std::string& text) {
    std::istringstream csv(text);
    std::string line;
    std::getline(csv, line);
    std::vector<std::pair<double, double>> rows;
    while (std::getline(csv, line)) {
        double x, y, z, v;
        char c;
        std::istringstream ls(line);
        ls >> x >> c >> y >> c >> z >> c >> v;
        rows.push_back({x, v});
    }
    return rows;
}

}  // namespace

TEST_CASE("meshless hierarchy: the same .mlh for 1 and 2 threads, lod and info read it", "[cli][cbt]") {
    TempDir d("hier_cli");
    const std::string vol = write_uint8_analytic_volume(d, "ml", AnalyticField::marschner_lobb, 24, 200, 20);
    const std::string D = d.path.string();
    // the dissertation's tree (max-error order, fitted values): its LOD's default c is 0.003 (below)
    const std::string paper = " --split-order max-error --cluster-value fit";
    REQUIRE(sh("MESHLESS hierarchy " + vol + paper + " -o " + D + "/t1.mlh --threads 1 --max-splits 3000", d).code == 0);
    const auto r2 = sh("MESHLESS hierarchy " + vol + paper + " -o " + D + "/t2.mlh --threads 2 --max-splits 3000 --stats", d);
    REQUIRE(r2.code == 0);
    CHECK(r2.err.find("3000 splits") != std::string::npos);
    CHECK(slurp(d / "t1.mlh") == slurp(d / "t2.mlh"));
    const ClusterTree t = read_cluster_tree_file(D + "/t1.mlh");
    CHECK(t.stats.samples == 24 * 24 * 24);

    const auto info = sh("MESHLESS info " + D + "/t1.mlh", d);
    REQUIRE(info.code == 0);
    CHECK(info.out.find("splits: 3000") != std::string::npos);
    CHECK(info.out.find("level-based LODs") != std::string::npos);

    // lod --level 8 as CSV: exactly the library's traversal, coarse to fine
    REQUIRE(sh("MESHLESS lod " + D + "/t1.mlh --level 8 -o " + D + "/l8.csv", d).code == 0);
    const auto ids = lod_coarse_to_fine_order(t.nodes, lod_nodes(t.nodes, LodMode::level, 8));
    const auto l8 = csv_x_and_value(slurp(d / "l8.csv"));
    REQUIRE(l8.size() == ids.size());
    for (std::size_t i = 0; i < l8.size(); ++i) {
        CHECK(l8[i].first == t.nodes[ids[i]].centre.x);
        CHECK(l8[i].second == t.nodes[ids[i]].value);
    }
    for (const char* ext : {"ply", "vtp"}) CHECK(sh("MESHLESS lod " + D + "/t1.mlh --error 30 -o " + D + "/e." + ext, d).code == 0);
    {
        // LOD samples are not splats: the VTP has positions and values, no (zero) Normals or radius
        const std::string vtp = slurp(d / "e.vtp");
        CHECK(vtp.find("Name=\"value\"") != std::string::npos);
        CHECK(vtp.find("Name=\"Normals\"") == std::string::npos);
        CHECK(vtp.find("Name=\"radius\"") == std::string::npos);
    }

    // beyond the tree: warn, finest LOD
    const auto deep = sh("MESHLESS lod " + D + "/t1.mlh --level 999 -o " + D + "/deep.csv", d);
    CHECK(deep.code == 0);
    CHECK(deep.err.find("beyond the depth") != std::string::npos);
    const auto low = sh("MESHLESS lod " + D + "/t1.mlh --error 0 -o " + D + "/low.csv", d);
    CHECK(low.code == 0);
    CHECK((t.stats.error_reached == 0 || low.err.find("below the error") != std::string::npos));
    CHECK(slurp(d / "deep.csv").size() > 0);

    // a point-set command reads the .mlh LOD as it reads the same points from a file; a LOD's
    // default Hardy c is 0.003 x the diagonal for a max-error tree (kLodHardyCRel), a file's 0.025, --hardy-c wins
    const std::string at = " --at 10,10,10 --at 5.5,12,3 --field mpu";
    const auto from_tree = sh("MESHLESS probe " + D + "/t1.mlh --lod-level 8 --stats" + at, d);
    const auto from_csv = sh("MESHLESS probe " + D + "/l8.csv --hardy-c 0.003 --stats" + at, d);
    REQUIRE(from_tree.code == 0);
    REQUIRE(from_csv.code == 0);
    CHECK(from_tree.out == from_csv.out);
    auto c_of = [](const std::string& err) {
        const auto at_c = err.find("c = ");
        return at_c == std::string::npos ? -1.0 : std::stod(err.substr(at_c + 4));
    };
    CHECK(c_of(from_tree.err) > 0);
    CHECK(c_of(from_tree.err) == c_of(from_csv.err));
    const auto tree_025 = sh("MESHLESS probe " + D + "/t1.mlh --lod-level 8 --hardy-c 0.025 --stats" + at, d);
    const auto csv_default = sh("MESHLESS probe " + D + "/l8.csv --stats" + at, d);
    REQUIRE(tree_025.code == 0);
    REQUIRE(csv_default.code == 0);
    CHECK(tree_025.out == csv_default.out);
    CHECK(c_of(csv_default.err) == Approx(c_of(from_tree.err) * 0.025 / 0.003).epsilon(1e-4));
    CHECK(tree_025.out != from_tree.out);
    const auto warned = sh("MESHLESS probe " + D + "/t1.mlh --lod-level 500" + at, d);
    CHECK(warned.code == 0);
    CHECK(warned.err.find("beyond the depth") != std::string::npos);
}

TEST_CASE("meshless lod --count/--fraction: the first N - 1 splits, and --lod-count reads the same", "[cli][cbt]") {
    TempDir d("hier_count");
    const std::string vol = write_uint8_analytic_volume(d, "ml", AnalyticField::marschner_lobb, 20, 200, 20);
    const std::string D = d.path.string();
    REQUIRE(sh("MESHLESS hierarchy " + vol + " -o " + D + "/t.mlh --max-splits 400", d).code == 0);
    const ClusterTree t = read_cluster_tree_file(D + "/t.mlh");
    CHECK(t.params.order == CbtSplitOrder::weighted);
    CHECK(t.params.value == CbtValueKind::mean);
    // --count 160 = --fraction 0.02 of 8000 samples: the same points, as the library lists them
    REQUIRE(sh("MESHLESS lod " + D + "/t.mlh --count 160 -o " + D + "/c.csv", d).code == 0);
    REQUIRE(sh("MESHLESS lod " + D + "/t.mlh --fraction 0.02 -o " + D + "/f.csv", d).code == 0);
    CHECK(slurp(d / "c.csv") == slurp(d / "f.csv"));
    const PointSet want = lod_point_set(t.nodes, LodMode::count, 160, t.value_name);
    REQUIRE(want.size() == 160);
    const auto got = csv_x_and_value(slurp(d / "c.csv"));
    REQUIRE(got.size() == 160);
    for (std::size_t i = 0; i < got.size(); ++i) {
        CHECK(got[i].first == want.pos[i].x);
        CHECK(got[i].second == want.value[i]);
    }
    const std::string at = " --at 10,10,10 --at 5.5,12,3 --field mpu --hardy-c 0.01";
    const auto a = sh("MESHLESS probe " + D + "/t.mlh --lod-count 160" + at, d), b = sh("MESHLESS probe " + D + "/c.csv" + at, d);
    REQUIRE(a.code == 0);
    CHECK(a.out == b.out);
    // the LOD's files carry its Hardy c (formats/field_hint.hpp): a field of the PLY or VTP is the
    // field of the .mlh's LOD without flags; --hardy-c still wins; CSV carries none. A weighted
    // tree's LOD takes the default c (0.025), a max-error tree's 0.003 (kernels/field_params.hpp)
    const std::string at0 = " --at 10,10,10 --at 5.5,12,3 --field mpu";
    const auto tree_default = sh("MESHLESS probe " + D + "/t.mlh --lod-count 160" + at0, d);
    REQUIRE(tree_default.code == 0);
    CHECK(sh("MESHLESS probe " + D + "/c.csv" + at0, d).out == tree_default.out);
    REQUIRE(sh("MESHLESS hierarchy " + vol + " --split-order max-error --cluster-value fit --max-splits 400 -o " + D + "/mx.mlh", d).code == 0);
    REQUIRE(sh("MESHLESS lod " + D + "/mx.mlh --count 160 -o " + D + "/mx.ply", d).code == 0);
    REQUIRE(sh("MESHLESS lod " + D + "/mx.mlh --count 160 -o " + D + "/mx.vtp", d).code == 0);
    REQUIRE(sh("MESHLESS lod " + D + "/mx.mlh --count 160 -o " + D + "/mx.csv", d).code == 0);
    CHECK(slurp(d / "mx.ply").find("comment meshless field: hardy-c-rel 0.003\n") != std::string::npos);
    const auto mx_tree = sh("MESHLESS probe " + D + "/mx.mlh --lod-count 160" + at0, d);
    REQUIRE(mx_tree.code == 0);
    CHECK(sh("MESHLESS probe " + D + "/mx.ply" + at0, d).out == mx_tree.out);
    CHECK(sh("MESHLESS probe " + D + "/mx.csv" + at0 + " --hardy-c 0.003", d).out == mx_tree.out);
    CHECK(sh("MESHLESS probe " + D + "/mx.csv" + at0, d).out != mx_tree.out);
    const auto vtp = sh("MESHLESS probe " + D + "/mx.vtp" + at0, d);  // float32 positions: compared with itself
    CHECK(vtp.out == sh("MESHLESS probe " + D + "/mx.vtp" + at0 + " --hardy-c 0.003", d).out);
    CHECK(vtp.out != sh("MESHLESS probe " + D + "/mx.vtp" + at0 + " --hardy-c 0.025", d).out);
    CHECK(sh("MESHLESS probe " + D + "/mx.ply" + at0 + " --hardy-c 0.01", d).out ==
          sh("MESHLESS probe " + D + "/mx.mlh --lod-count 160" + at0 + " --hardy-c 0.01", d).out);
    // beyond the leaves: warn, the finest
    const auto many = sh("MESHLESS lod " + D + "/t.mlh --count 100000 -o " + D + "/m.csv", d);
    CHECK(many.code == 0);
    CHECK(many.err.find("more than the tree's 401 leaves") != std::string::npos);
    // usage errors: exit 1, one line, nothing written
    for (const std::string bad : {"--count 0", "--fraction 0", "--fraction 1.5", "--count 5 --level 2", "--fraction nan"}) {
        const auto r = sh("MESHLESS lod " + D + "/t.mlh " + bad + " -o " + D + "/bad.csv", d);
        INFO(bad << ": " << r.err);
        CHECK(r.code == 1);
        CHECK(one_line(r.err));
        CHECK_FALSE(std::filesystem::exists(d / "bad.csv"));
    }
    for (const std::string bad : {"--split-order best", "--size-term -1", "--size-term 101", "--cluster-value median"}) {
        const auto r = sh("MESHLESS hierarchy " + vol + " " + bad + " -o " + D + "/bad.mlh", d);
        INFO(bad << ": " << r.err);
        CHECK(r.code == 1);
        CHECK(one_line(r.err));
        CHECK_FALSE(std::filesystem::exists(d / "bad.mlh"));
    }
    // the dissertation's tree: max-error order, fitted values, recorded in the file and in info
    REQUIRE(sh("MESHLESS hierarchy " + vol + " --split-order max-error --cluster-value fit --max-splits 50 -o " + D + "/m.mlh", d).code == 0);
    const auto info = sh("MESHLESS info " + D + "/m.mlh", d);
    CHECK(info.out.find("split order max-error") != std::string::npos);
    CHECK(info.out.find("cluster value fit") != std::string::npos);
}

TEST_CASE("meshless lod: cluster values beyond the samples' range are kept and warned about", "[cli][cbt]") {
    // newcomer trial 2: lod of a uint8 set wrote values down to -1.05 without a word. Values 0 or
    // 100 at random on a jittered grid: a cluster's fit at its centre overshoots them.
    TempDir d("lod_range");
    std::string rows;
    unsigned r = 5;
    auto u = [&] { r = r * 1103515245u + 12345u; return (r >> 8) / double(1 << 24); };
    for (int i = 0; i < 8; ++i)
        for (int j = 0; j < 8; ++j)
            for (int k = 0; k < 8; ++k)
                rows += std::to_string(i + 0.6 * u() - 0.3) + "," + std::to_string(j + 0.6 * u() - 0.3) + "," +
                        std::to_string(k + 0.6 * u() - 0.3) + "," + (u() < 0.5 ? "0" : "100") + "\n";
    const std::string csv = write_csv(d, "noisy.csv", rows), D = d.path.string();
    REQUIRE(sh("MESHLESS hierarchy " + csv + " --cluster-value fit -o " + D + "/n.mlh", d).code == 0);  // means cannot overshoot
    const ClusterTree t = read_cluster_tree_file(D + "/n.mlh");
    std::uint32_t depth = 0;
    for (const CbtNode& n : t.nodes) depth = std::max(depth, n.depth);
    bool warned = false, quiet = false;
    for (std::uint32_t level = 0; level <= depth; ++level) {
        const auto ids = lod_nodes(t.nodes, LodMode::level, level);
        bool outside = false;
        for (const auto id : ids) outside = outside || t.nodes[id].value < 0 || t.nodes[id].value > 100;
        const auto l = sh("MESHLESS lod " + D + "/n.mlh --level " + std::to_string(level) + " -o " + D + "/l.csv", d);
        REQUIRE(l.code == 0);
        const bool said = l.err.find("cluster values lie outside the samples' range [0, 100]") != std::string::npos;
        CHECK(said == outside);  // exactly when some value of that level lies outside
        warned = warned || said;
        quiet = quiet || !said;
    }
    CHECK(warned);  // the data makes some level overshoot ...
    CHECK(quiet);   // ... and some not (the finest: the samples themselves)
}

TEST_CASE("meshless hierarchy: bad input is one line, non-zero, nothing written", "[cli][cbt]") {
    TempDir d("hier_bad");
    const std::string D = d.path.string();
    auto refused = [&](const std::string& input, const std::string& what) {
        const auto r = sh("MESHLESS hierarchy " + input + " -o " + D + "/bad.mlh", d);
        INFO(input << ": " << r.err);
        CHECK(r.code != 0);
        CHECK(one_line(r.err));
        CHECK(r.err.find(what) != std::string::npos);
        CHECK_FALSE(std::filesystem::exists(d / "bad.mlh"));
    };
    refused(write_csv(d, "one.csv", "1,2,3,4\n"), "valid point");
    refused(write_csv(d, "same.csv", "1,2,3,4\n1,2,3,5\n1,2,3,6\n1,2,3,7\n1,2,3,8\n"), "one position");
    refused(write_csv(d, "nan.csv", "1,2,3,4\nnan,2,3,5\n1,inf,3,6\n1,2,3,nan\n2,2,3,nan\n"), "NaN/Inf");
    // NaN rows dropped and counted, the rest builds
    const auto nan = sh("MESHLESS hierarchy " + write_csv(d, "nan2.csv", "0,0,0,1\nnan,2,3,5\n1,0,0,2\n0,1,0,3\n0,0,1,4\n1,1,1,nan\n") +
                            " -o " + D + "/nan.mlh",
                        d);
    CHECK(nan.code == 0);
    CHECK(nan.err.find("2 samples with NaN/Inf") != std::string::npos);
    CHECK(read_cluster_tree_file(D + "/nan.mlh").stats.dropped_nonfinite == 2);
    // a constant field: a one-node tree
    const auto flat = sh("MESHLESS hierarchy " + write_csv(d, "flat.csv", "0,0,0,5\n1,0,0,5\n0,1,0,5\n0,0,1,5\n1,1,1,5\n") + " -o " + D +
                             "/flat.mlh",
                         d);
    CHECK(flat.code == 0);
    CHECK(read_cluster_tree_file(D + "/flat.mlh").nodes.size() == 1);
    // collinear samples
    CHECK(sh("MESHLESS hierarchy " + write_csv(d, "line.csv", "0,0,0,1\n1,1,1,2\n2,2,2,0\n3,3,3,7\n4,4,4,1\n") + " -o " + D + "/line.mlh", d)
              .code == 0);
    // usage errors
    CHECK(sh("MESHLESS hierarchy " + D + "/line.csv -o " + D + "/x.ply", d).code == 1);
    CHECK(sh("MESHLESS hierarchy " + D + "/line.csv -o " + D + "/x.mlh --min-cluster 1", d).code == 1);
    CHECK(sh("MESHLESS lod " + D + "/line.mlh -o " + D + "/x.csv", d).code == 1);
    CHECK(sh("MESHLESS lod " + D + "/line.mlh --level 1 --error 2 -o " + D + "/x.csv", d).code == 1);
    // a damaged .mlh: exit 2, one line naming the file
    std::string bytes = slurp(d / "line.mlh");
    bytes.resize(bytes.size() - 3);
    spit(d / "cut.mlh", bytes);
    const auto cut = sh("MESHLESS lod " + D + "/cut.mlh --level 1 -o " + D + "/x.csv", d);
    CHECK(cut.code == 2);
    CHECK(one_line(cut.err));
    CHECK(cut.err.find("cut.mlh") != std::string::npos);
    CHECK_FALSE(std::filesystem::exists(d / "x.csv"));
}

TEST_CASE("meshless hierarchy: a raw volume described by --dims/--type gives the tree of the same voxels from NRRD",
          "[cli][cbt]") {
    TempDir d("hier_cli_raw");
    const std::string D = d.path.string();
    // 6 x 5 x 4 uint8 voxels, the same bytes as a headerless raw file and behind an NRRD header
    std::string bytes;
    for (int i = 0; i < 6 * 5 * 4; ++i) bytes += static_cast<char>((i * 37) % 251);
    spit(d / "v.dat", bytes);
    spit(d / "v.nhdr", "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 6 5 4\nspacings: 2 1 1\nencoding: raw\ndata file: v.dat\n");
    spit(d / "plain.raw", bytes);
    REQUIRE(sh("MESHLESS hierarchy " + D + "/v.nhdr -o " + D + "/n.mlh", d).code == 0);
    const auto r = sh("MESHLESS hierarchy " + D + "/plain.raw --dims 6,5,4 --type uint8 --spacing 2,1,1 -o " + D + "/r.mlh", d);
    REQUIRE(r.code == 0);
    const ClusterTree a = read_cluster_tree_file(D + "/n.mlh"), b = read_cluster_tree_file(D + "/r.mlh");
    CHECK(a.stats.samples == 120);
    REQUIRE(a.nodes.size() == b.nodes.size());
    for (std::size_t i = 0; i < a.nodes.size(); ++i) {
        CHECK(a.nodes[i].centre.x == b.nodes[i].centre.x);
        CHECK(a.nodes[i].value == b.nodes[i].value);
        CHECK(a.nodes[i].child == b.nodes[i].child);
    }
    // a raw file whose name gives its shape takes --spacing alone (it was ignored without --dims/--type)
    spit(d / "named_6x5x4_uint8.raw", bytes);
    REQUIRE(sh("MESHLESS hierarchy " + D + "/named_6x5x4_uint8.raw --spacing 2,1,1 -o " + D + "/s.mlh", d).code == 0);
    const ClusterTree s = read_cluster_tree_file(D + "/s.mlh");
    REQUIRE(s.nodes.size() == a.nodes.size());
    for (std::size_t i = 0; i < a.nodes.size(); ++i) CHECK(a.nodes[i].centre.x == s.nodes[i].centre.x);
    // dims that do not match the file: one line naming it, nothing written
    const auto bad = sh("MESHLESS hierarchy " + D + "/plain.raw --dims 6,5,5 --type uint8 -o " + D + "/bad.mlh", d);
    CHECK(bad.code != 0);
    CHECK(one_line(bad.err));
    CHECK(bad.err.find("plain.raw") != std::string::npos);
    CHECK(!std::filesystem::exists(d / "bad.mlh"));
    // --dims with two inputs is a usage error
    CHECK(sh("MESHLESS hierarchy " + D + "/plain.raw " + D + "/plain.raw --dims 6,5,4 --type uint8 -o " + D + "/x.mlh", d).code != 0);
}

TEST_CASE("meshless lod --max-error: within E at every sample, and one point fewer is not", "[cli][cbt]") {
    TempDir d("hier_cert");
    const std::string vol = write_uint8_analytic_volume(d, "ml", AnalyticField::marschner_lobb, 12, 200, 20);
    const std::string D = d.path.string();
    REQUIRE(sh("MESHLESS hierarchy " + vol + " -o " + D + "/t.mlh", d).code == 0);  // the full tree
    const ClusterTree t = read_cluster_tree_file(D + "/t.mlh");
    const PointSet samples = point_set_from_volume(vol);
    FieldParams fp;  // what a reader of the LOD uses: mpu, a weighted tree's c (the default)
    fp.kind = FieldKind::mpu;
    auto max_error = [&](const PointSet& lod) {
        const auto f = make_field(lod, fp);
        std::vector<double> v(samples.size());
        f->evaluate(samples.pos, v, {});
        double m = 0;
        for (std::size_t i = 0; i < v.size(); ++i) m = std::max(m, std::isnan(v[i]) ? INFINITY : std::abs(v[i] - samples.value[i]));
        return m;
    };
    for (const double e : {40.0, 10.0}) {
        const auto r = sh("MESHLESS lod " + D + "/t.mlh --max-error " + std::to_string(e) + " --samples " + vol + " -o " + D +
                              "/c.ply --stats",
                          d);
        REQUIRE(r.code == 0);
        const std::size_t n = lod_nodes(t.nodes, LodMode::count, 1e18).size();  // the leaves
        // the count the command chose, from its --stats line "N points, max error ..."
        const auto at = r.err.find("t.mlh: ");
        REQUIRE(at != std::string::npos);
        const std::uint64_t count = std::stoull(r.err.substr(at + 7));
        REQUIRE(count >= 1);
        REQUIRE(count <= n);
        const PointSet lod = lod_point_set(t.nodes, LodMode::count, static_cast<double>(count), t.value_name);
        INFO("E " << e << ": " << count << " points");
        CHECK(max_error(lod) <= e);  // checked independently at every sample
        if (count > 1) CHECK(max_error(lod_point_set(t.nodes, LodMode::count, static_cast<double>(count - 1), t.value_name)) > e);
        CHECK(slurp(d / "c.ply").find("comment meshless field: hardy-c-rel 0.025\n") != std::string::npos);
    }
    // a tree too shallow for E: the finest level of detail written, a warning, and exit 4 for scripts
    REQUIRE(sh("MESHLESS hierarchy " + vol + " --max-splits 20 -o " + D + "/small.mlh", d).code == 0);
    const auto unreached = sh("MESHLESS lod " + D + "/small.mlh --max-error 0.001 --samples " + vol + " -o " + D + "/u.ply", d);
    CHECK(unreached.code == 4);
    CHECK(unreached.err.find("no level of detail reaches --max-error") != std::string::npos);
    CHECK(std::filesystem::exists(d / "u.ply"));
    // the samples of another data set: exit 2 naming it, nothing written
    const std::string other = write_uint8_analytic_volume(d, "other", AnalyticField::marschner_lobb, 10, 200, 20);
    const auto bad = sh("MESHLESS lod " + D + "/t.mlh --max-error 10 --samples " + other + " -o " + D + "/bad.ply", d);
    CHECK(bad.code == 2);
    CHECK(bad.err.find("not the tree's") != std::string::npos);
    CHECK_FALSE(std::filesystem::exists(d / "bad.ply"));
    // the same grid with its values inverted: the same count and bounds, another hash
    const std::string name = std::filesystem::path(vol).filename().string();
    std::string inverted = slurp(vol);
    for (char& c : inverted) c = static_cast<char>(255 - static_cast<unsigned char>(c));
    spit(d / ("inv" + name.substr(name.find('_'))), inverted);
    const auto inv = sh("MESHLESS lod " + D + "/t.mlh --max-error 10 --samples " + D + "/inv" + name.substr(name.find('_')) + " -o " + D +
                            "/inv.ply",
                        d);
    CHECK(inv.code == 2);
    CHECK(inv.err.find("not the tree's: the same count and bounds, other positions or values (their hash differs)") != std::string::npos);
    CHECK_FALSE(std::filesystem::exists(d / "inv.ply"));
}

TEST_CASE("meshless hierarchy --certify: info lists the error of each size, as probe of the lod's points measures it", "[cli][cbt]") {
    TempDir d("hier_certify");
    const std::string vol = write_uint8_analytic_volume(d, "ml", AnalyticField::marschner_lobb, 12, 200, 20);
    const std::string D = d.path.string();
    REQUIRE(sh("MESHLESS hierarchy " + vol + " -o " + D + "/plain.mlh", d).code == 0);
    REQUIRE(sh("MESHLESS hierarchy " + vol + " --certify 0.15,0.05,0.05 -o " + D + "/t.mlh --threads 2", d).code == 0);
    REQUIRE(sh("MESHLESS hierarchy " + vol + " --certify 0.05,0.15 -o " + D + "/t1.mlh --threads 1", d).code == 0);
    CHECK(slurp(d / "t.mlh") == slurp(d / "t1.mlh"));  // the same bytes for any thread count and order of the sizes
    const ClusterTree plain = read_cluster_tree_file(D + "/plain.mlh");
    const ClusterTree t = read_cluster_tree_file(D + "/t.mlh");
    CHECK(plain.certified.empty());
    CHECK(cluster_tree_file_version(D + "/plain.mlh") == 4);
    CHECK(cluster_tree_file_version(D + "/t.mlh") == 4);
    CHECK(t.nodes.size() == plain.nodes.size());
    REQUIRE(t.certified.size() == 2);  // 0.05 twice is one size
    const PointSet samples = point_set_from_volume(vol);
    for (const CertifiedError& c : t.certified) {
        CHECK(c.count == static_cast<std::uint64_t>(std::llround((c.count == t.certified[0].count ? 0.05 : 0.15) * samples.size())));
        CHECK(c.hardy_c_rel == 0.025);  // a weighted tree's LOD c, the one its files carry
        // oracle: the lod's file read back by probe (the c from its comment) at every sample
        const std::string lod = D + "/l" + std::to_string(c.count) + ".ply";
        REQUIRE(sh("MESHLESS lod " + D + "/t.mlh --count " + std::to_string(c.count) + " -o " + lod, d).code == 0);
        std::string at;
        for (const Vec3& p : samples.pos) at += std::to_string(p.x) + "," + std::to_string(p.y) + "," + std::to_string(p.z) + "\n";
        spit(d / "at.csv", at);
        const auto r = sh("MESHLESS probe " + lod + " --at-file " + D + "/at.csv --max-gap 0", d);
        REQUIRE(r.code == 0);
        std::istringstream csv(r.out);
        std::string line;
        std::getline(csv, line);
        double worst = 0;
        for (std::size_t i = 0; std::getline(csv, line); ++i) {
            std::istringstream row(line);
            std::string cell;
            for (int k = 0; k < 4; ++k) std::getline(row, cell, ',');
            worst = std::max(worst, std::abs(std::stod(cell) - samples.value[i]));
        }
        INFO(c.count << " points");
        CHECK(worst == Approx(c.max_error).epsilon(1e-6));  // (the CSV prints 7 digits)
    }
    const auto info = sh("MESHLESS info " + D + "/t.mlh", d);
    REQUIRE(info.code == 0);
    CHECK(info.out.find(".mlh version 4") != std::string::npos);
    CHECK(info.out.find("certified errors (meshless lod --count N") != std::string::npos);
    char row[64];
    std::snprintf(row, sizeof row, "%14.6g", t.certified[1].max_error);
    CHECK(info.out.find(row) != std::string::npos);
    CHECK(sh("MESHLESS info " + D + "/plain.mlh", d).out.find("certified errors: none") != std::string::npos);
    // lod --max-error at a certified error: the certified size bounds the search (never a larger LOD)
    {
        const CertifiedError& c = t.certified[0];
        char e[64];
        std::snprintf(e, sizeof e, "%.17g", c.max_error);
        const auto r = sh("MESHLESS lod " + D + "/t.mlh --max-error " + e + " --samples " + vol + " -o " + D + "/c.ply --stats", d);
        REQUIRE(r.code == 0);
        const auto at = r.err.find("t.mlh: ");
        REQUIRE(at != std::string::npos);
        CHECK(std::stoull(r.err.substr(at + 7)) <= c.count);
    }
    // bad sizes: one line, exit 1, nothing written
    for (const char* bad : {"0", "1.5", "nan", "0.1,-0.2"}) {
        const auto r = sh("MESHLESS hierarchy " + vol + " --certify " + bad + " -o " + D + "/bad.mlh", d);
        CHECK(r.code == 1);
        CHECK(one_line(r.err));
        CHECK_FALSE(std::filesystem::exists(d / "bad.mlh"));
    }
}
