// `meshless isosurface POINTS` (dissertation chapter 5) and its pipes as a user runs them, on point
// sets written by the test: identical bytes in-process, across pipes (generate | project --field
// F.mlf | write / splat) and for any --threads (also with --dedup); points on the sampled sphere;
// the --stats report; and the pathological inputs of scattered data, each with its answer: planar and
// collinear points (a warning naming the degeneracy, a surface where the field defines one), two
// clusters 1e6 apart, a grid bounded by --max-cells (coarsened, with a warning), duplicated points,
// 1e6 coordinate offsets, fewer than 4 distinct points (exit 2, nothing written), NaN/Inf positions
// and values (dropped and counted), an isovalue outside the value range (warning, empty valid
// outputs).
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <random>
#include <string>

#include "cli/cli_harness.hpp"
#include "formats/ply_points.hpp"
#include "formats/png_reader.hpp"

using namespace meshless;
using namespace meshless::test;
namespace fs = std::filesystem;

namespace {

struct P4 {
    double x, y, z, v;
};

std::string write_csv(const TempDir& d, const std::string& name, const std::vector<P4>& pts, const std::vector<std::string>& extra = {}) {
    std::string s = "x,y,z,value\n";
    char buf[160];
    for (const P4& p : pts) {
        std::snprintf(buf, sizeof buf, "%.17g,%.17g,%.17g,%.17g\n", p.x, p.y, p.z, p.v);
        s += buf;
    }
    for (const auto& e : extra) s += e + "\n";
    spit(d / name, s);
    return (d / name).string();
}

/// n uniform points in [-1,1]^3 (times scale, plus offset) with value |p - offset| / scale.
std::vector<P4> sphere_points(int n, unsigned seed, double scale = 1, Vec3 offset = {0, 0, 0}) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(-1, 1);
    std::vector<P4> p;
    for (int i = 0; i < n; ++i) {
        const Vec3 x{u(rng), u(rng), u(rng)};
        p.push_back({offset.x + scale * x.x, offset.y + scale * x.y, offset.z + scale * x.z, norm(x)});
    }
    return p;
}

/// Largest | |p - c| / scale - r | over the points of a PLY.
double worst_sphere_error(const std::string& ply, double r, Vec3 c = {0, 0, 0}, double scale = 1) {
    const PlyPoints p = read_ply_points(ply);
    double worst = 0;
    for (const auto& q : p.points) worst = std::max(worst, std::abs(norm(Vec3{q.pos[0], q.pos[1], q.pos[2]} - c) / scale - r));
    return worst;
}

std::size_t ply_count(const std::string& ply) { return read_ply_points(ply).points.size(); }

}  // namespace

TEST_CASE("isosurface POINTS: in-process, piped and any --threads give the same bytes", "[cli][scattered]") {
    TempDir d("scpipe");
    const std::string pts = write_csv(d, "sphere.csv", sphere_points(4000, 1));
    const std::string D = d.path.string();
    REQUIRE(sh("MESHLESS fit " + pts + " --field rbf-grid -o " + D + "/f.mlf", d).code == 0);
    const std::string common = " --iso 0.6 --samples 2 --field " + D + "/f.mlf";
    auto r = sh("MESHLESS isosurface " + pts + common + " --threads 1 -o " + D + "/a.ply --png " + D + "/a.png --size 160x160 --stats", d);
    REQUIRE(r.code == 0);
    for (const char* s : {"binning level 3", "regularisation points", "Delaunay failures", "tets", "seeds", "converged",
                          "octree + binning", "field", "regularisation", "isosurface (stencils"})
        CHECK_THAT(r.err, Catch::Contains(s));
    REQUIRE(sh("MESHLESS isosurface " + pts + common + " --threads 2 -o " + D + "/b.ply --png " + D + "/b.png --size 160x160", d).code == 0);
    REQUIRE(sh("MESHLESS generate " + pts + " --iso 0.6 --samples 2 --field " + D + "/f.mlf --threads 2 | MESHLESS project --field " + D +
                   "/f.mlf --threads 3 | MESHLESS write -o " + D + "/c.ply",
               d).code == 0);
    REQUIRE(sh("MESHLESS generate " + pts + " --iso 0.6 --samples 2 --field " + D + "/f.mlf --compress | MESHLESS project --field " + D +
                   "/f.mlf | MESHLESS splat -o " + D + "/c.png --size 160x160",
               d).code == 0);
    const std::string a = slurp(d / "a.ply");
    CHECK(a.size() > 20000);
    CHECK_THAT(a, Catch::Contains("comment field rbf-grid"));
    CHECK_THAT(a, !Catch::Contains("property uint block"));
    CHECK(a == slurp(d / "b.ply"));
    CHECK(a == slurp(d / "c.ply"));
    CHECK(slurp(d / "a.png") == slurp(d / "b.png"));
    CHECK(slurp(d / "a.png") == slurp(d / "c.png"));
    // a field built in place (no .mlf): the same field, the same bytes
    REQUIRE(sh("MESHLESS isosurface " + pts + " --iso 0.6 --samples 2 --field rbf-grid --threads 2 -o " + D + "/e.ply", d).code == 0);
    REQUIRE(sh("MESHLESS generate " + pts + " --iso 0.6 --samples 2 | MESHLESS project --field rbf-grid " + pts + " | MESHLESS write -o " +
                   D + "/g.ply",
               d).code == 0);
    CHECK(slurp(d / "e.ply") == a);
    CHECK(slurp(d / "g.ply") == a);
    // the VTP too: no `block` array for a scattered set (the in-process sink wrote the seeds' zero
    // block ids, the pipe's stream carries none)
    REQUIRE(sh("MESHLESS isosurface " + pts + common + " -o " + D + "/a.vtp", d).code == 0);
    REQUIRE(sh("MESHLESS generate " + pts + common + " | MESHLESS project --field " + D + "/f.mlf | MESHLESS write -o " + D + "/c.vtp",
               d).code == 0);
    const std::string av = slurp(d / "a.vtp");
    CHECK_THAT(av, Catch::Contains("Name=\"Normals\""));
    CHECK_THAT(av, !Catch::Contains("Name=\"block\""));
    CHECK(av == slurp(d / "c.vtp"));
    // the points lie on the sphere |p| = 0.6 (the rbf-grid field of |p| reproduces it closely)
    CHECK(worst_sphere_error((d / "a.ply").string(), 0.6) < 0.02);
}

TEST_CASE("isosurface POINTS builds chapter 5's MPU field by default, fit chooses by the data", "[cli][scattered][fit]") {
    TempDir d("scdefault");
    const std::string pts = write_csv(d, "sphere.csv", sphere_points(3000, 5));
    const std::string D = d.path.string();
    auto r = sh("MESHLESS isosurface " + pts + " --iso 0.6 -o " + D + "/a.ply --stats", d);
    REQUIRE(r.code == 0);
    CHECK_THAT(r.err, Catch::Contains("mpu field from 3000 points"));
    CHECK_THAT(r.err, Catch::Contains("Newton onto mpu"));
    CHECK_THAT(slurp(d / "a.ply"), Catch::Contains("comment field mpu"));
    CHECK(worst_sphere_error((d / "a.ply").string(), 0.6) < 0.02);
    // the same bytes as naming it, and as the pipe through a field fitted with fit's default
    REQUIRE(sh("MESHLESS isosurface " + pts + " --iso 0.6 --field mpu -o " + D + "/b.ply", d).code == 0);
    CHECK(slurp(d / "a.ply") == slurp(d / "b.ply"));
    REQUIRE(sh("MESHLESS fit " + pts + " -o " + D + "/f.mlf", d).code == 0);
    CHECK_THAT(sh("MESHLESS info " + D + "/f.mlf", d).out, Catch::Contains("field: mpu"));
    REQUIRE(sh("MESHLESS generate " + pts + " --iso 0.6 | MESHLESS project --field " + D + "/f.mlf | MESHLESS write -o " + D + "/c.ply", d)
                .code == 0);
    CHECK(slurp(d / "a.ply") == slurp(d / "c.ply"));
    // the help says which field is built
    CHECK_THAT(sh("MESHLESS isosurface " + pts + " --help", d).out, Catch::Contains("(default mpu)"));
    // probe, slice and resample build the field fit fits: the same bytes as through the .mlf, not
    // those of rbf-grid
    const std::string at = " --at 0.1,0.2,0.3 --at 0.5,0,0 --at 0,0,0.62";
    auto probe = [&](const std::string& field) { return sh("MESHLESS probe " + pts + at + field, d); };
    const auto p_default = probe(" --stats");
    REQUIRE(p_default.code == 0);
    CHECK_THAT(p_default.err, Catch::Contains("mpu field from 3000 points"));
    CHECK(p_default.out == probe(" --field " + D + "/f.mlf").out);
    CHECK(p_default.out != probe(" --field rbf-grid").out);
    for (const std::string& cmd : {"slice " + pts + " --plane z=0.1 --size 40x40 -o " + D + "/s", "resample " + pts + " --grid 9,9,9 -o " + D + "/r"}) {
        const std::string ext = cmd.rfind("slice", 0) == 0 ? ".png" : ".nrrd";
        REQUIRE(sh("MESHLESS " + cmd + "1" + ext, d).code == 0);
        REQUIRE(sh("MESHLESS " + cmd + "2" + ext + " --field " + D + "/f.mlf", d).code == 0);
        REQUIRE(sh("MESHLESS " + cmd + "3" + ext + " --field rbf-grid", d).code == 0);
        const std::string base = cmd.substr(cmd.rfind(D));
        CHECK(slurp(base + "1" + ext) == slurp(base + "2" + ext));
        CHECK(slurp(base + "1" + ext) != slurp(base + "3" + ext));
        CHECK_THAT(sh("MESHLESS " + cmd.substr(0, cmd.find(' ')) + " --help", d).out,
                   Catch::Contains("mpu for point sets, rbf-grid for multiblock inputs"));
    }
    // multiblock inputs keep chapter 4's RBF grid
    if (have_shared_data()) {
        const std::string P = (shared_data() / "plot3d").string();
        REQUIRE(sh("MESHLESS fit " + P + "/multicomb_0.vts -o " + D + "/mb.mlf", d).code == 0);
        CHECK_THAT(sh("MESHLESS info " + D + "/mb.mlf", d).out, Catch::Contains("field: rbf-grid"));
        const auto pb = sh("MESHLESS probe " + P + "/multicomb_0.vts --at 3,0,0 --stats", d);
        REQUIRE(pb.code == 0);
        CHECK_THAT(pb.err, Catch::Contains("rbf-grid field from"));
    }
}

TEST_CASE("isosurface POINTS: the recorded frame (bounds_lo/hi) holds every point of the surface", "[cli][scattered]") {
    TempDir d("scframe");
    const std::string D = d.path.string();
    // boreholes: the surface bulges up to ~2 km beyond the outermost samples (cut off in --png when
    // the frame was the points' box)
    std::vector<std::string> inputs{write_csv(d, "sphere.csv", sphere_points(3000, 5))};
    std::vector<std::string> isos{" --iso 0.6"};
    if (have_shared_data()) {
        inputs.push_back((shared_data() / "scattered" / "probes" / "probes.vtp").string());
        isos.push_back(" --iso 150");
        // points Newton moved beyond the grid's border layer (up to --max-travel cell diagonals)
        inputs.push_back((shared_data() / "scattered" / "Particles.raw").string());
        isos.push_back(" --iso 6");
        inputs.push_back(inputs.back());
        isos.push_back(" --iso 6 --max-travel 6");
        // generate | project with a longer travel widens the frame as isosurface does: the same bytes
        const std::string P = inputs.back();
        REQUIRE(sh("MESHLESS generate " + P + " --iso 6 | MESHLESS project --field mpu " + P + " --max-travel 6 | MESHLESS write -o " +
                       D + "/piped.ply", d).code == 0);
        REQUIRE(sh("MESHLESS isosurface " + P + " --iso 6 --max-travel 6 -o " + D + "/inproc.ply", d).code == 0);
        CHECK(slurp(d / "piped.ply") == slurp(d / "inproc.ply"));
    }
    for (std::size_t i = 0; i < inputs.size(); ++i) {
        const std::string out = D + "/f" + std::to_string(i) + ".ply";
        REQUIRE(sh("MESHLESS isosurface " + inputs[i] + isos[i] + " -o " + out, d).code == 0);
        const PlyPoints p = read_ply_points(out);
        REQUIRE(p.points.size() > 100);
        Vec3 lo{0, 0, 0}, hi{0, 0, 0};
        for (const std::string& c : p.comments) {
            double v[3];
            if (std::sscanf(c.c_str(), "bounds_lo %lf,%lf,%lf", &v[0], &v[1], &v[2]) == 3) lo = {v[0], v[1], v[2]};
            if (std::sscanf(c.c_str(), "bounds_hi %lf,%lf,%lf", &v[0], &v[1], &v[2]) == 3) hi = {v[0], v[1], v[2]};
        }
        REQUIRE(hi.x > lo.x);
        std::size_t outside = 0;
        for (const auto& q : p.points)
            for (int a = 0; a < 3; ++a) outside += q.pos[a] < lo[a] - 1e-6 * (hi[a] - lo[a]) || q.pos[a] > hi[a] + 1e-6 * (hi[a] - lo[a]);
        CHECK(outside == 0);
    }
}

TEST_CASE("isosurface POINTS --dedup: fewer points, still on the surface, same bytes for any --threads", "[cli][scattered]") {
    TempDir d("scdedup");
    const std::string pts = write_csv(d, "sphere.csv", sphere_points(3000, 2));
    const std::string D = d.path.string();
    REQUIRE(sh("MESHLESS isosurface " + pts + " --iso 0.5 --threads 1 -o " + D + "/all.ply", d).code == 0);
    auto r = sh("MESHLESS isosurface " + pts + " --iso 0.5 --dedup 0.5 --threads 1 --stats -o " + D + "/a.ply --png " + D + "/a.png --size 96x96", d);
    REQUIRE(r.code == 0);
    CHECK_THAT(r.err, Catch::Contains("near-duplicate points"));
    REQUIRE(sh("MESHLESS isosurface " + pts + " --iso 0.5 --dedup 0.5 --threads 2 -o " + D + "/b.ply --png " + D + "/b.png --size 96x96", d).code == 0);
    CHECK(slurp(d / "a.ply") == slurp(d / "b.ply"));
    CHECK(slurp(d / "a.png") == slurp(d / "b.png"));
    const std::size_t all = ply_count((d / "all.ply").string()), kept = ply_count((d / "a.ply").string());
    CHECK(kept < all * 3 / 4);
    CHECK(kept > all / 10);
    // no two kept points closer than half the radius of the later one
    const PlyPoints p = read_ply_points((d / "a.ply").string());
    std::size_t close = 0;
    for (std::size_t i = 0; i < p.points.size() && i < 3000; ++i)
        for (std::size_t j = 0; j < i; ++j) {
            const auto& a = p.points[i].pos;
            const auto& b = p.points[j].pos;
            const double dist = std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]));
            close += dist < 0.5 * p.points[i].radius * (1 - 1e-5);
        }
    CHECK(close == 0);
    CHECK(sh("MESHLESS isosurface " + pts + " --iso 0.5 --dedup -1 -o " + D + "/x.ply", d).code == 1);
}

TEST_CASE("isosurface POINTS: planar and collinear points warn and name the degeneracy", "[cli][scattered]") {
    TempDir d("scdegen");
    std::mt19937_64 rng(4);
    std::uniform_real_distribution<double> u(-1, 1);
    std::vector<P4> plane, line;
    for (int i = 0; i < 2000; ++i) {
        const double x = u(rng), y = u(rng);
        plane.push_back({x, y, 3.0, x});  // value = x: the surface x = iso crosses the plane
        const double z = u(rng);
        line.push_back({5.0, -2.0, z, z});
    }
    const std::string D = d.path.string();
    auto r = sh("MESHLESS isosurface " + write_csv(d, "plane.csv", plane) + " --iso 0.25 --stats -o " + D + "/p.ply", d);
    REQUIRE(r.code == 0);
    CHECK_THAT(r.err, Catch::Contains("all points lie on a plane"));
    CHECK_THAT(r.err, Catch::Contains("along z"));
    const PlyPoints pp = read_ply_points((d / "p.ply").string());
    REQUIRE(pp.points.size() > 100);
    // where the data is (the plane z = 3) the surface is x = 0.25
    std::size_t near_plane = 0;
    for (const auto& q : pp.points)
        if (std::abs(q.pos[2] - 3.0) < 0.05) {
            ++near_plane;
            CHECK(std::abs(q.pos[0] - 0.25) < 0.02);
        }
    CHECK(near_plane > 20);
    r = sh("MESHLESS isosurface " + write_csv(d, "line.csv", line) + " --iso 0.25 -o " + D + "/l.ply", d);
    REQUIRE(r.code == 0);
    CHECK_THAT(r.err, Catch::Contains("all points lie on a line"));
    CHECK_THAT(r.err, Catch::Contains("along x, y"));
    CHECK(fs::exists(d / "l.ply"));
}

TEST_CASE("isosurface POINTS: two clusters 1e6 apart, and a grid bounded by --max-cells", "[cli][scattered]") {
    TempDir d("scclust");
    std::vector<P4> pts = sphere_points(1500, 5, 1.0);
    for (const P4& p : sphere_points(1500, 6, 1.0, {1e6, 1e6, 1e6})) pts.push_back(p);
    const std::string D = d.path.string();
    const std::string f = write_csv(d, "clusters.csv", pts);
    // the depth-first rule stops at the root (one stencil holds both clusters, section 5.8) and the
    // fields cannot resolve 1-unit detail over a 1e6 box: a bounded run, regularisation points far
    // from the data get no value, the seeds that do not converge are dropped, counted and warned about
    auto r = sh("MESHLESS isosurface " + f + " --iso 0.5 --stats -o " + D + "/c.ply --png " + D + "/c.png --size 64x64", d);
    REQUIRE(r.code == 0);
    CHECK_THAT(r.err, Catch::Contains("binning level 0"));
    CHECK_THAT(r.err, Catch::Contains("(26 beyond --reg-gap)"));
    CHECK_THAT(r.err, Catch::Contains("did not converge onto the mpu field"));
    const PlyPoints c = read_ply_points((d / "c.ply").string());
    for (const auto& q : c.points) {
        const bool second = q.pos[0] > 5e5;
        const Vec3 ctr = second ? Vec3{1e6, 1e6, 1e6} : Vec3{0, 0, 0};
        CHECK(norm(Vec3{q.pos[0], q.pos[1], q.pos[2]} - ctr) < 2);  // nothing in the empty space between
    }
    CHECK(fs::file_size(d / "c.png") > 0);
    // a dense set whose rule level needs more cells than allowed: coarsened, with a warning
    const std::string dense = write_csv(d, "dense.csv", sphere_points(20000, 7));
    r = sh("MESHLESS isosurface " + dense + " --iso 0.5 --max-cells 1000 --stats -o " + D + "/m.ply", d);
    REQUIRE(r.code == 0);
    CHECK_THAT(r.err, Catch::Contains("coarsened to level 3"));
    CHECK_THAT(r.err, Catch::Contains("binning level 3 (rule 4, coarsened)"));
    CHECK(ply_count((d / "m.ply").string()) > 1000);
    CHECK(sh("MESHLESS isosurface " + dense + " --iso 0.5 --max-cells 26 -o " + D + "/x.ply", d).code == 1);
}

TEST_CASE("isosurface POINTS: duplicated points and 1e6 coordinate offsets", "[cli][scattered]") {
    TempDir d("scdup");
    const std::string D = d.path.string();
    std::vector<P4> pts = sphere_points(3000, 8);
    std::vector<P4> dup = pts;
    for (int i = 0; i < 1000; ++i) dup.push_back(pts[static_cast<std::size_t>(i)]);
    for (int i = 0; i < 300; ++i) dup.push_back(pts[0]);
    REQUIRE(sh("MESHLESS isosurface " + write_csv(d, "dup.csv", dup) + " --iso 0.6 -o " + D + "/d.ply", d).code == 0);
    CHECK(ply_count((d / "d.ply").string()) > 1000);
    CHECK(worst_sphere_error((d / "d.ply").string(), 0.6) < 0.03);
    // offset by 1e6 and scaled by 100: the same surface, moved (float positions: 1e6 + 100 x quantised to 1/16)
    const Vec3 off{1e6, -3e6, 2e6};
    REQUIRE(sh("MESHLESS isosurface " + write_csv(d, "off.csv", sphere_points(3000, 8, 100, off)) + " --iso 0.6 -o " + D + "/o.ply", d).code == 0);
    CHECK(ply_count((d / "o.ply").string()) > 1000);
    CHECK(worst_sphere_error((d / "o.ply").string(), 0.6, off, 100) < 0.03);
}

TEST_CASE("isosurface POINTS: fewer than 4 distinct points is a data error, NaN/Inf points are dropped and counted", "[cli][scattered]") {
    TempDir d("scbad");
    const std::string D = d.path.string();
    const std::vector<P4> three = {{0, 0, 0, 1}, {1, 0, 0, 2}, {0, 1, 0, 3}, {0, 0, 0, 1}, {1, 0, 0, 2}, {0, 1, 0, 3}};
    auto r = sh("MESHLESS isosurface " + write_csv(d, "three.csv", three) + " --iso 1.5 -o " + D + "/t.ply --png " + D + "/t.png", d);
    CHECK(r.code == 2);
    CHECK_THAT(r.err, Catch::Contains("three.csv"));
    CHECK_THAT(r.err, Catch::Contains("fewer than 4 distinct"));
    CHECK_FALSE(fs::exists(d / "t.ply"));
    CHECK_FALSE(fs::exists(d / "t.png"));
    CHECK(sh("MESHLESS generate " + (d / "three.csv").string() + " --iso 1.5 -o " + D + "/t.seeds", d).code == 2);
    CHECK_FALSE(fs::exists(d / "t.seeds"));
    const std::string nan = write_csv(d, "nan.csv", sphere_points(2000, 9), {"nan,0,0,1", "0,inf,0,1", "0.1,0.1,0.1,nan", "0.2,0.2,0.2,-inf"});
    r = sh("MESHLESS isosurface " + nan + " --iso 0.6 --stats -o " + D + "/n.ply", d);
    REQUIRE(r.code == 0);
    CHECK_THAT(r.err, Catch::Contains("4 points with a NaN/Inf position or value dropped"));
    CHECK_THAT(r.err, Catch::Contains("2000 points (4 NaN/Inf dropped)"));
    CHECK(ply_count((d / "n.ply").string()) > 1000);
    // every command that reads points says so once, under its own name; --strict refuses them
    for (const std::string cmd : {"fit " + nan + " -o " + D + "/n.mlf", "probe " + nan + " --at 0,0,0",
                                  "isosurface " + nan + " --iso 0.6 -o " + D + "/n2.ply"}) {
        INFO(cmd);
        r = sh("MESHLESS " + cmd, d);
        CHECK(r.code == 0);
        const std::string w = "meshless " + cmd.substr(0, cmd.find(' ')) + ": warning: " + nan +
                              ": 4 points with a NaN/Inf position or value dropped";
        CHECK_THAT(r.err, Catch::Contains(w));
        CHECK(r.err.find("NaN/Inf") == r.err.rfind("NaN/Inf"));
    }
    r = sh("MESHLESS fit " + nan + " --strict -o " + D + "/s.mlf", d);
    CHECK(r.code == 2);
    CHECK_FALSE(fs::exists(d / "s.mlf"));
}

TEST_CASE("isosurface POINTS: an isovalue outside the value range warns and writes empty valid outputs", "[cli][scattered]") {
    TempDir d("scrange");
    const std::string D = d.path.string();
    const std::string pts = write_csv(d, "sphere.csv", sphere_points(2000, 10));
    auto r = sh("MESHLESS isosurface " + pts + " --iso 7 --stats -o " + D + "/e.ply --png " + D + "/e.png --size 64x64", d);
    CHECK(r.code == 0);
    CHECK_THAT(r.err, Catch::Contains("outside the data range"));
    const std::string e = slurp(d / "e.ply");
    CHECK_THAT(e, Catch::Contains("element vertex 0"));
    CHECK(read_ply_points((d / "e.ply").string()).points.empty());
    CHECK(fs::file_size(d / "e.png") > 0);
    r = sh("MESHLESS generate " + pts + " --iso 7 | MESHLESS project --field mpu " + pts + " | MESHLESS write -o " + D + "/f.ply", d);
    CHECK(r.code == 0);
    CHECK(slurp(d / "f.ply") == e);
}

TEST_CASE("mpirun -np 2 isosurface POINTS gives the single-process bytes", "[cli][scattered][mpi]") {
    TempDir d("scmpi");
    const std::string mpirun = mpirun_prefix(d);
    if (mpirun.empty()) {
        WARN("mpirun not installed: MPI test skipped");
        return;
    }
    const std::string D = d.path.string();
    const std::string pts = write_csv(d, "sphere.csv", sphere_points(4000, 12));
    const std::string common = " --iso 0.6 --threads 1 --size 96x96 --stats";
    REQUIRE(sh("MESHLESS isosurface " + pts + common + " -o " + D + "/one.ply --png " + D + "/one.png", d).code == 0);
    auto r = sh(mpirun + "MESHLESS isosurface " + pts + common + " -o " + D +
                    "/two.ply --png " + D + "/two.png",
                d);
    REQUIRE(r.code == 0);
    CHECK_THAT(r.err, Catch::Contains("over 2 ranks"));
    // every rank builds the field (the fits shared); rank 0 alone reports it
    std::size_t reports = 0;
    for (std::size_t at = r.err.find("mpu field from"); at != std::string::npos; at = r.err.find("mpu field from", at + 1)) ++reports;
    CHECK(reports == 1);
    CHECK(slurp(d / "one.ply").size() > 10000);
    CHECK(slurp(d / "one.ply") == slurp(d / "two.ply"));
    CHECK(slurp(d / "one.png") == slurp(d / "two.png"));
    // three ranks, with --dedup on rank 0's side: still the single-process bytes
    REQUIRE(sh("MESHLESS isosurface " + pts + " --iso 0.6 --dedup 0.5 -o " + D + "/dd1.ply", d).code == 0);
    REQUIRE(sh(mpirun_prefix(d, 3) + "MESHLESS isosurface " + pts + " --iso 0.6 --dedup 0.5 -o " + D +
                   "/dd3.ply",
               d).code == 0);
    CHECK(slurp(d / "dd1.ply") == slurp(d / "dd3.ply"));
    // a failing rank (fewer than 4 distinct points: every rank fails) fails the job with no output
    const std::vector<P4> three = {{0, 0, 0, 1}, {1, 0, 0, 2}, {0, 1, 0, 3}};
    r = sh(mpirun + "MESHLESS isosurface " + write_csv(d, "three.csv", three) +
               " --iso 1.5 -o " + D + "/bad.ply",
           d);
    CHECK(r.code != 0);
    CHECK_FALSE(fs::exists(d / "bad.ply"));
}

TEST_CASE("isosurface POINTS: the picture frames the surface itself and not the recorded box", "[cli][scattered]") {
    // the recorded bounds hold every point (the binning grid, its border layer and Newton's travel:
    // a box many times the surface's width); pictures frame the points themselves, spooled first,
    // in-process, through pipes and from the PLY alike
    TempDir d("scpicture");
    const std::string D = d.path.string();
    const std::string pts = write_csv(d, "sphere.csv", sphere_points(3000, 5));
    REQUIRE(sh("MESHLESS isosurface " + pts + " --iso 0.6 -o " + D + "/s.ply --png " + D + "/a.png --size 200x200", d).code == 0);
    REQUIRE(sh("MESHLESS generate " + pts + " --iso 0.6 | MESHLESS project --field mpu " + pts + " | MESHLESS splat -o " + D +
                   "/b.png --size 200x200", d).code == 0);
    REQUIRE(sh("MESHLESS splat " + D + "/s.ply -o " + D + "/c.png --size 200x200", d).code == 0);
    CHECK(slurp(d / "a.png") == slurp(d / "b.png"));
    CHECK(slurp(d / "a.png") == slurp(d / "c.png"));
    const Image img = read_png(D + "/a.png");
    int x0 = img.width, x1 = -1, y0 = img.height, y1 = -1;
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) {
            const auto c = img.at(x, y);
            if (c[0] == 0 && c[1] == 0 && c[2] == 0) continue;
            x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
        }
    INFO("surface spans " << x1 - x0 + 1 << " x " << y1 - y0 + 1 << " pixels of 200 x 200");
    CHECK(x1 - x0 + 1 >= 80);  // was 15 x 16 framed on the recorded box
    CHECK(y1 - y0 + 1 >= 80);
}
