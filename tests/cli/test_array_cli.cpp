// --array NAME on the volume commands: the point array of a .vti / VTK legacy .vtk holding several.
// Oracle: a command on a multi-array file with --array B gives the bytes it gives on a file holding
// only B (same geometry); without --array, the bytes of the array read before --array existed (the
// active scalars, else the first). info lists the arrays; a missing name exits 2 naming the file and
// its arrays; --array on a format of one unnamed array (raw) or a brick store exits 1.
#include <catch2/catch.hpp>

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "cli/cli_harness.hpp"
#include "formats/ply_points.hpp"
#include "kernels/analytic_volumes.hpp"
#include "kernels/multiblock_split.hpp"

using namespace meshless;
using namespace meshless::test;
namespace fs = std::filesystem;

namespace {

constexpr std::int64_t kN = 24;

// The float32 samples of an analytic field as VTK XML ascii text (%.9g: every float reads back exactly).
std::string ascii_samples(AnalyticField f) {
    const Volume v = make_analytic_volume(f, kN);
    const float* p = reinterpret_cast<const float*>(v.bytes.data());
    std::string s;
    char buf[32];
    for (std::int64_t i = 0; i < v.grid.voxel_count(); ++i) {
        std::snprintf(buf, sizeof buf, "%.9g%c", static_cast<double>(p[i]), i % 8 == 7 ? '\n' : ' ');
        s += buf;
    }
    return s;
}

// A .vti of the analytic grid (origin -1, spacing 2/(n-1)) holding the named arrays, in order.
std::string vti(const std::vector<std::pair<std::string, AnalyticField>>& arrays, const std::string& scalars = "") {
    const std::string e = "0 " + std::to_string(kN - 1) + " 0 " + std::to_string(kN - 1) + " 0 " + std::to_string(kN - 1);
    char sp[64];
    std::snprintf(sp, sizeof sp, "%.17g %.17g %.17g", 2.0 / (kN - 1), 2.0 / (kN - 1), 2.0 / (kN - 1));
    std::string s = "<?xml version=\"1.0\"?>\n<VTKFile type=\"ImageData\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
                    "<ImageData WholeExtent=\"" + e + "\" Origin=\"-1 -1 -1\" Spacing=\"" + sp + "\">\n<Piece Extent=\"" + e +
                    "\">\n<PointData" + (scalars.empty() ? "" : " Scalars=\"" + scalars + "\"") + ">\n";
    for (const auto& [name, f] : arrays)
        s += "<DataArray type=\"Float32\" Name=\"" + name + "\" format=\"ascii\">\n" + ascii_samples(f) + "</DataArray>\n";
    return s + "</PointData>\n</Piece>\n</ImageData>\n</VTKFile>\n";
}

// A legacy ASCII .vtk of the same grid holding the named SCALARS arrays, in order.
std::string legacy(const std::vector<std::pair<std::string, AnalyticField>>& arrays) {
    char sp[96];
    std::snprintf(sp, sizeof sp, "SPACING %.17g %.17g %.17g\n", 2.0 / (kN - 1), 2.0 / (kN - 1), 2.0 / (kN - 1));
    const std::string n = std::to_string(kN);
    std::string s = "# vtk DataFile Version 3.0\nanalytic\nASCII\nDATASET STRUCTURED_POINTS\nDIMENSIONS " + n + " " + n + " " + n +
                    "\n" + sp + "ORIGIN -1 -1 -1\nPOINT_DATA " + std::to_string(kN * kN * kN) + "\n";
    for (const auto& [name, f] : arrays) s += "SCALARS " + name + " float 1\nLOOKUP_TABLE default\n" + ascii_samples(f);
    return s;
}

// A PLY's bytes less its comment lines (they record the input's name, and pad the header after it):
// the header's elements and properties, and the points.
std::string points_of(const std::string& bytes) { return lines_without(bytes, "comment "); }
std::string without_names(const fs::path& p) { return points_of(slurp(p)); }

}  // namespace

TEST_CASE("array choice: isosurface and mc of a multi-array .vti equal those of a file holding only that array", "[cli][arrays]") {
    TempDir d("array-cli");
    const std::string D = d.path.string();
    spit(d / "in_multi.vti", vti({{"sphere", AnalyticField::sphere}, {"torus", AnalyticField::torus}}));
    spit(d / "in_active.vti", vti({{"sphere", AnalyticField::sphere}, {"torus", AnalyticField::torus}}, "torus"));
    spit(d / "in_sphere.vti", vti({{"sphere", AnalyticField::sphere}}));
    spit(d / "in_torus.vti", vti({{"torus", AnalyticField::torus}}));
    const auto run = [&](const std::string& args) {
        const RunResult r = sh("MESHLESS " + args, d);
        INFO(args << "\n" << r.err);
        REQUIRE(r.code == 0);
    };
    // the named array: the points of the single-array file, byte for byte
    run("isosurface " + D + "/in_multi.vti --array torus --iso 0.25 -o " + D + "/multi_torus.ply");
    run("isosurface " + D + "/in_torus.vti --iso 0.25 -o " + D + "/torus.ply");
    CHECK(without_names(d / "multi_torus.ply") == without_names(d / "torus.ply"));
    // the default: the first array (no Scalars), the active scalars where the file names them
    run("isosurface " + D + "/in_multi.vti --iso 0.6 -o " + D + "/multi_default.ply");
    run("isosurface " + D + "/in_sphere.vti --iso 0.6 -o " + D + "/sphere.ply");
    CHECK(without_names(d / "multi_default.ply") == without_names(d / "sphere.ply"));
    run("isosurface " + D + "/in_active.vti --iso 0.25 -o " + D + "/active_default.ply");
    CHECK(without_names(d / "active_default.ply") == without_names(d / "torus.ply"));
    run("isosurface " + D + "/in_active.vti --array sphere --iso 0.6 -o " + D + "/active_sphere.ply");
    CHECK(without_names(d / "active_sphere.ply") == without_names(d / "sphere.ply"));
    // another command reading the volume whole
    run("mc " + D + "/in_multi.vti --array torus --iso 0.25 -o " + D + "/mc_multi.ply");
    run("mc " + D + "/in_torus.vti --iso 0.25 -o " + D + "/mc_torus.ply");
    CHECK(without_names(d / "mc_multi.ply") == without_names(d / "mc_torus.ply"));
    // convert: the brick store of the named array holds the single file's samples
    run("convert " + D + "/in_multi.vti --array torus -o " + D + "/multi.mlb");
    run("convert " + D + "/in_torus.vti -o " + D + "/torus.mlb");
    CHECK(slurp(d / "multi.mlb") == slurp(d / "torus.mlb"));
}

TEST_CASE("array choice: a legacy .vtk with two SCALARS arrays", "[cli][arrays]") {
    TempDir d("array-cli-vtk");
    const std::string D = d.path.string();
    spit(d / "in_two.vtk", legacy({{"sphere", AnalyticField::sphere}, {"torus", AnalyticField::torus}}));
    spit(d / "in_torus.vtk", legacy({{"torus", AnalyticField::torus}}));
    spit(d / "in_sphere.vtk", legacy({{"sphere", AnalyticField::sphere}}));
    for (const auto& [args, want] : std::vector<std::pair<std::string, std::string>>{
             {"/in_two.vtk --array torus --iso 0.25", "/in_torus.vtk --iso 0.25"},
             {"/in_two.vtk --iso 0.6", "/in_sphere.vtk --iso 0.6"}}) {
        INFO(args);
        REQUIRE(sh("MESHLESS isosurface " + D + args + " -o " + D + "/a.ply", d).code == 0);
        REQUIRE(sh("MESHLESS isosurface " + D + want + " -o " + D + "/b.ply", d).code == 0);
        CHECK(without_names(d / "a.ply") == without_names(d / "b.ply"));
    }
    const RunResult r = sh("MESHLESS info " + D + "/in_two.vtk", d);
    CHECK(r.code == 0);
    CHECK(r.out.find("point arrays: 2") != std::string::npos);
    CHECK(r.out.find("    sphere: float32, 1 component; read, the default\n") != std::string::npos);
    CHECK(r.out.find("    torus: float32, 1 component\n") != std::string::npos);
}

TEST_CASE("array choice: info lists the arrays, a missing name exits 2 naming the file and its arrays, "
          "raw files and brick stores refuse it", "[cli][arrays]") {
    TempDir d("array-cli-info");
    const std::string D = d.path.string();
    spit(d / "in_multi.vti", vti({{"sphere", AnalyticField::sphere}, {"torus", AnalyticField::torus}}));
    RunResult r = sh("MESHLESS info " + D + "/in_multi.vti", d);
    REQUIRE(r.code == 0);
    CHECK(r.out.find("  point arrays: 2 (read one with --array NAME)\n"
                     "    sphere: float32, 1 component; read, the default\n"
                     "    torus: float32, 1 component\n") != std::string::npos);
    r = sh("MESHLESS info " + D + "/in_multi.vti --array torus", d);
    REQUIRE(r.code == 0);
    CHECK(r.out.find("    sphere: float32, 1 component; the default\n"
                     "    torus: float32, 1 component; read (--array)\n") != std::string::npos);
    // a single-array file lists nothing more than before
    spit(d / "in_one.vti", vti({{"sphere", AnalyticField::sphere}}));
    r = sh("MESHLESS info " + D + "/in_one.vti", d);
    CHECK(r.code == 0);
    CHECK(r.out.find("point arrays") == std::string::npos);

    // a name the file lacks: exit 2, one line naming the file and the arrays it has
    for (const std::string cmd : {"isosurface", "mc", "info"}) {
        INFO(cmd);
        r = sh("MESHLESS " + cmd + " " + D + "/in_multi.vti --array density" + (cmd == "info" ? "" : " --iso 0.5 -o " + D + "/x.ply"), d);
        CHECK(r.code == 2);
        CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
        CHECK(r.err.find(D + "/in_multi.vti: no point array named 'density'; its arrays: 'sphere' (float32), 'torus' (float32)") !=
              std::string::npos);
        CHECK(!fs::exists(d / "x.ply"));
    }
    // a raw file (one unnamed array): a usage error
    write_uint8_analytic_volume(d, "raw", AnalyticField::sphere, 16, 100, 0);
    r = sh("MESHLESS isosurface " + D + "/raw_16x16x16_uint8.raw --array sphere --iso 50 -o " + D + "/x.ply", d);
    CHECK(r.code == 1);
    CHECK(r.err.find("raw_16x16x16_uint8.raw: a raw volume holds one unnamed array") != std::string::npos);
    CHECK(sh("MESHLESS info " + D + "/raw_16x16x16_uint8.raw --array sphere", d).code == 1);
    CHECK(sh("MESHLESS mc " + D + "/raw_16x16x16_uint8.raw --array sphere --iso 50 -o " + D + "/x.ply", d).code == 1);
    CHECK(sh("MESHLESS isosurface " + D + "/raw_16x16x16_uint8.raw --array \"\" --iso 50 -o " + D + "/x.ply", d).code == 1);
    // a brick store holds one array: a usage error for every command that reads it
    REQUIRE(sh("MESHLESS convert " + D + "/raw_16x16x16_uint8.raw -o " + D + "/v.mlb", d).code == 0);
    for (const std::string& cmd : {"isosurface " + D + "/v.mlb --iso 50 -o " + D + "/x.ply", "mc " + D + "/v.mlb --iso 50 -o " + D + "/x.ply",
                                   "info " + D + "/v.mlb", "convert " + D + "/v.mlb -o " + D + "/w.mlb",
                                   "render " + D + "/v.mlb -o " + D + "/x.png --size 32x32",
                                   "hierarchy " + D + "/v.mlb -o " + D + "/x.mlh"}) {
        INFO(cmd);
        r = sh("MESHLESS " + cmd + " --array sphere", d);
        CHECK(r.code == 1);
        CHECK(r.err.find("v.mlb") != std::string::npos);
        CHECK(r.err.find("one unnamed array") != std::string::npos);
    }
    CHECK(!fs::exists(d / "x.ply"));
    CHECK(!fs::exists(d / "w.mlb"));
}

TEST_CASE("array choice on real data: hydrogen.vti and ironProt.vtk with a second array added", "[cli][arrays][real]") {
    if (!have_shared_data()) {
        WARN("shared data not found: skipped");
        return;
    }
    TempDir d("array-cli-real");
    const std::string D = d.path.string();
    // hydrogen.vti: its one array (binary, zlib) copied under another name before it; Scalars still
    // names the original, so the default stays the original's and --array copy reads the same bytes
    const std::string h = slurp(shared_data() / "vtk_hydrogen" / "hydrogen.vti");
    const std::size_t a0 = h.find("<DataArray"), a1 = h.find("</DataArray>") + 12;
    REQUIRE(a0 != std::string::npos);
    std::string copy = h.substr(a0, a1 - a0);
    copy.replace(copy.find("Name=\"probability_density\""), 26, "Name=\"copy\"");
    spit(d / "in_h2.vti", h.substr(0, a0) + copy + "\n" + h.substr(a0));
    REQUIRE(sh("MESHLESS isosurface " + shared_data().string() + "/vtk_hydrogen/hydrogen.vti --iso 0.1 -o " + D + "/h.ply", d).code == 0);
    for (const std::string opt : {"", " --array copy", " --array probability_density"}) {
        INFO(opt);
        REQUIRE(sh("MESHLESS isosurface " + D + "/in_h2.vti --iso 0.1 -o " + D + "/h2.ply" + opt, d).code == 0);
        CHECK(without_names(d / "h2.ply") == without_names(d / "h.ply"));
    }
    RunResult r = sh("MESHLESS info " + D + "/in_h2.vti", d);
    CHECK(r.out.find("    copy: float32, 1 component\n    probability_density: float32, 1 component; read, the default\n") !=
          std::string::npos);
    r = sh("MESHLESS info " + shared_data().string() + "/vtk_hydrogen/hydrogen.vti --array density", d);
    CHECK(r.code == 2);
    CHECK(r.err.find("hydrogen.vti: no point array named 'density'; its arrays: 'probability_density' (float32)") != std::string::npos);

    // ironProt.vtk (BINARY): a second SCALARS array appended, the bytes inverted; --array inverted
    // equals a single-array file of the inverted bytes, the default the original file
    const std::string v = slurp(shared_data() / "vtk_ironProt" / "ironProt.vtk");
    const std::size_t n = 68 * 68 * 68, head = v.size() - n - 1;
    std::string inv = v.substr(head, n);
    for (char& c : inv) c = static_cast<char>(255 - static_cast<unsigned char>(c));
    spit(d / "in_iron2.vtk", v + "SCALARS inverted unsigned_char\nLOOKUP_TABLE default\n" + inv + "\n");
    std::string single = v.substr(0, head) + inv + "\n";
    spit(d / "in_inv.vtk", single);
    REQUIRE(sh("MESHLESS isosurface " + D + "/in_iron2.vtk --array inverted --iso 200 -o " + D + "/a.ply", d).code == 0);
    REQUIRE(sh("MESHLESS isosurface " + D + "/in_inv.vtk --iso 200 -o " + D + "/b.ply", d).code == 0);
    CHECK(without_names(d / "a.ply") == without_names(d / "b.ply"));
    REQUIRE(sh("MESHLESS isosurface " + D + "/in_iron2.vtk --iso 128 -o " + D + "/c.ply", d).code == 0);
    REQUIRE(sh("MESHLESS isosurface " + shared_data().string() + "/vtk_ironProt/ironProt.vtk --iso 128 -o " + D + "/o.ply", d).code == 0);
    CHECK(without_names(d / "c.ply") == without_names(d / "o.ply"));
    r = sh("MESHLESS info " + D + "/in_iron2.vtk", d);
    CHECK(r.out.find("point arrays: 2") != std::string::npos);
    CHECK(r.out.find("    inverted: uint8, 1 component\n") != std::string::npos);
}

TEST_CASE("array choice on a batch manifest line: the store of the named array, recorded in its sidecar", "[cli][arrays][batch]") {
    TempDir d("array-cli-batch");
    const fs::path arch = d / "arch", out = d / "out";
    fs::create_directories(arch);
    spit(arch / "in_multi.vti", vti({{"sphere", AnalyticField::sphere}, {"torus", AnalyticField::torus}}));
    spit(arch / "in_torus.vti", vti({{"torus", AnalyticField::torus}}));
    spit(arch / "in_other.vti", vti({{"sphere", AnalyticField::sphere}, {"torus", AnalyticField::torus}}));
    spit(arch / "list.txt", "in_multi.vti --array torus\nin_torus.vti\nin_other.vti --array density\n");
    const RunResult r = sh("MESHLESS batch " + (arch / "list.txt").string() + " -o " + out.string() + " --iso 0.25", d);
    CHECK(r.code == 2);  // in_other: no such array, reported alone
    CHECK_THAT(r.err, Catch::Contains("in_other.vti: no point array named 'density'; its arrays: 'sphere' (float32), 'torus' (float32)"));
    CHECK_THAT(r.out, Catch::Contains("3 volume(s): 2 done, 0 up to date, 1 failed"));
    CHECK(slurp(out / "in_multi.mlb") == slurp(out / "in_torus.mlb"));
    CHECK_THAT(slurp(out / "in_multi.mlb.meta"), Catch::Contains("param.raw=array=torus"));
    CHECK(points_of(slurp(out / "in_multi_iso0.25.ply")) == points_of(slurp(out / "in_torus_iso0.25.ply")));
}

TEST_CASE("isosurface --color-by ARRAY: each point's value is the other array's trilinear value there, the points unchanged",
          "[cli][arrays]") {
    TempDir d("color-by");
    const std::string D = d.path.string();
    spit(d / "two.vti", vti({{"sphere", AnalyticField::sphere}, {"torus", AnalyticField::torus}}));
    REQUIRE(sh("MESHLESS isosurface " + D + "/two.vti --iso 0.6 -o " + D + "/plain.ply --png " + D + "/plain.png --size 64x64", d).code == 0);
    const RunResult r = sh("MESHLESS isosurface " + D + "/two.vti --iso 0.6 --color-by torus -o " + D + "/c.ply --png " + D +
                               "/c.png --size 64x64",
                           d);
    INFO(r.err);
    REQUIRE(r.code == 0);
    const PlyPoints plain = read_ply_points((d / "plain.ply").string()), c = read_ply_points((d / "c.ply").string());
    REQUIRE(c.points.size() == plain.points.size());
    REQUIRE(c.points.size() > 100);
    // oracle: the torus array sampled at each point (the same analytic grid the file holds)
    const Volume torus = make_analytic_volume(AnalyticField::torus, kN);
    int differs = 0;
    for (std::size_t i = 0; i < c.points.size(); ++i) {
        const PointRecord &p = c.points[i], &q = plain.points[i];
        CHECK(std::memcmp(p.pos, q.pos, sizeof p.pos) == 0);  // the same surface
        CHECK(std::memcmp(p.normal, q.normal, sizeof p.normal) == 0);
        const double want = sample_trilinear(torus.view(), Vec3{p.pos[0], p.pos[1], p.pos[2]});
        CHECK(p.value == static_cast<float>(want));
        differs += p.value != q.value;
    }
    CHECK(differs > 0);
    const std::string bytes = slurp(d / "c.ply");
    CHECK(bytes.find("comment value_name torus\n") != std::string::npos);
    CHECK(bytes.find("comment iso 0.") != std::string::npos);  // the surface's isovalue stays recorded
    CHECK(slurp(d / "c.png") != slurp(d / "plain.png"));          // coloured by the array
    // splat of the point set draws the picture isosurface --png drew: coloured by the array over its
    // recorded range, the legend titled with its name
    REQUIRE(sh("MESHLESS isosurface " + D + "/two.vti --iso 0.6 --color-by torus -o " + D + "/c.ply --png " + D +
                   "/cbar.png --size 96x96 --colorbar",
               d).code == 0);
    REQUIRE(sh("MESHLESS splat " + D + "/c.ply -o " + D + "/s.png --size 96x96 --colorbar", d).code == 0);
    CHECK(slurp(d / "s.png") == slurp(d / "cbar.png"));
    // a VTP names its value array after the array the values are (ParaView lists "torus"), and reads back
    REQUIRE(sh("MESHLESS isosurface " + D + "/two.vti --iso 0.6 --color-by torus -o " + D + "/c.vtp", d).code == 0);
    const std::string vtp = slurp(d / "c.vtp");
    CHECK(vtp.find("Scalars=\"torus\"") != std::string::npos);
    CHECK(vtp.find("Name=\"torus\"") != std::string::npos);
    CHECK(vtp.find("Name=\"value\"") == std::string::npos);
    REQUIRE(sh("MESHLESS splat " + D + "/c.vtp -o " + D + "/sv.png --size 96x96 --colorbar", d).code == 0);
    REQUIRE(sh("MESHLESS isosurface " + D + "/two.vti --iso 0.6 -o " + D + "/plain.vtp", d).code == 0);
    CHECK(slurp(d / "plain.vtp").find("Scalars=\"value\"") != std::string::npos);  // (an isosurface's own values: "value")
    // a missing array: exit 2 naming the file's arrays; a sample store or an empty name: exit 1, nothing written
    const RunResult missing = sh("MESHLESS isosurface " + D + "/two.vti --iso 0.6 --color-by nope -o " + D + "/m.ply", d);
    CHECK(missing.code == 2);
    CHECK(missing.err.find("'sphere'") != std::string::npos);
    CHECK_FALSE(fs::exists(d / "m.ply"));
    CHECK(sh("MESHLESS isosurface " + D + "/two.vti --iso 0.6 --color-by '' -o " + D + "/m.ply", d).code == 1);
    REQUIRE(sh("MESHLESS convert " + D + "/two.vti -o " + D + "/two.mlb", d).code == 0);
    REQUIRE(sh("MESHLESS generate " + D + "/two.mlb --all -o " + D + "/two.mls", d).code == 0);
    const RunResult store = sh("MESHLESS isosurface " + D + "/two.mls --iso 0.6 --color-by torus -o " + D + "/m.ply", d);
    CHECK(store.code == 1);
    CHECK(store.err.find("sample store") != std::string::npos);
    CHECK(sh("MESHLESS isosurface " + D + "/two.mlb --iso 0.6 --color-by torus -o " + D + "/m.ply", d).code != 0);
    CHECK_FALSE(fs::exists(d / "m.ply"));
}
