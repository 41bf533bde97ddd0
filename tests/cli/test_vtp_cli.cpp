// VTP outputs end to end (formats/vtp_writer.hpp through `isosurface`, `write`, `mc`): VTK's own
// reader (vtkXMLPolyDataReader, python3-vtk9; skipped with a warning when no python3 imports vtk)
// reads the files, and every array equals the PLY written by the same command (the oracle: the
// PLY path, parsed independently in Python); identical bytes for any --threads and through
// pipes; the choice by extension and --format; nothing left by a refused command.
#include <catch2/catch.hpp>

#include <algorithm>
#include <filesystem>

#include "cli/cli_harness.hpp"
#include "formats/ply.hpp"
#include "kernels/colormap.hpp"

#include <cmath>
#include <vector>

using namespace meshless;
using namespace meshless::test;

namespace {

/// A python3 that imports vtk ("" when none): the PATH one, else Debian's.
std::string vtk_python(const TempDir& d) {
    for (const char* py : {"python3", "/usr/bin/python3"})
        if (sh(std::string(py) + " -c \"import vtk\"", d).code == 0) return py;
    return "";
}

// Reads A.vtp with VTK and A.ply by hand (binary little endian, the layouts the writers use);
// exits 1 with a message on any difference. argv: kind (points|mesh) vtp ply
const char* kCompare = R"PY(
import sys, struct, numpy as np, vtk
from vtk.util.numpy_support import vtk_to_numpy as v2n
kind, vtp, ply = sys.argv[1:4]
r = vtk.vtkXMLPolyDataReader(); r.SetFileName(vtp); r.Update()
if r.GetErrorCode() != 0: sys.exit("vtk reader error %d" % r.GetErrorCode())
p = r.GetOutput()
data = open(ply, "rb").read()
end = data.index(b"end_header\n") + len(b"end_header\n")
head = data[:end].decode()
counts = {l.split()[1]: int(l.split()[2]) for l in head.splitlines() if l.startswith("element")}
props = [l.split()[-1] for l in head.splitlines() if l.startswith("property") and "list" not in l]
def check(name, a, b):
    a = np.asarray(a); b = np.asarray(b)
    if a.shape != b.shape or not np.array_equal(a, b, equal_nan=True):
        sys.exit("%s differs: %s vs %s" % (name, a.shape, b.shape))
pd = p.GetPointData()
if kind == "points":
    n = counts["vertex"]
    rec = np.frombuffer(data, dtype="<f4", count=8 * n, offset=end).reshape(n, 8)
    if p.GetNumberOfPoints() != n or p.GetNumberOfVerts() != n: sys.exit("counts %d %d vs %d" % (p.GetNumberOfPoints(), p.GetNumberOfVerts(), n))
    check("points", v2n(p.GetPoints().GetData()), rec[:, 0:3])
    if pd.GetNormals() is None or pd.GetNormals().GetName() != "Normals": sys.exit("no Normals attribute")
    if pd.GetScalars() is None or pd.GetScalars().GetName() != "value": sys.exit("no value Scalars attribute")
    check("Normals", v2n(pd.GetNormals()), rec[:, 3:6])
    check("radius", v2n(pd.GetArray("radius")), rec[:, 6])
    check("value", v2n(pd.GetArray("value")), rec[:, 7])
    cells = v2n(p.GetVerts().GetConnectivityArray()); offs = v2n(p.GetVerts().GetOffsetsArray())
    check("verts", cells, np.arange(n)); check("vert offsets", offs, np.arange(n + 1))
else:
    nv, nf = counts["vertex"], counts["face"]
    blocks = "block" in props
    vr = np.frombuffer(data, dtype="<f4", count=6 * nv, offset=end).reshape(nv, 6)
    fdt = np.dtype([("n", "u1"), ("i", "<i4", 3)] + ([("b", "<u4")] if blocks else []))
    fr = np.frombuffer(data, dtype=fdt, count=nf, offset=end + 24 * nv)
    if p.GetNumberOfPoints() != nv or p.GetNumberOfPolys() != nf: sys.exit("counts")
    check("points", v2n(p.GetPoints().GetData()), vr[:, 0:3])
    check("Normals", v2n(pd.GetNormals()), vr[:, 3:6])
    check("triangles", v2n(p.GetPolys().GetConnectivityArray()).reshape(nf, 3), fr["i"])
    if blocks: check("block", v2n(p.GetCellData().GetArray("block")), fr["b"])
print("ok", p.GetNumberOfPoints(), p.GetNumberOfCells())
)PY";

}  // namespace

TEST_CASE("vtp: isosurface, write and mc -o .vtp, VTK reads what the PLY holds, same bytes for any --threads", "[cli][vtp]") {
    TempDir d("vtp-cli");
    const std::string vol = write_uint8_analytic_volume(d, "torus", AnalyticField::torus, 40, 200.0, 0.0);
    const std::string D = d.path.string() + "/";
    REQUIRE(sh("MESHLESS isosurface " + vol + " --iso 50.5 --threads 1 -o " + D + "a.ply", d).code == 0);
    REQUIRE(sh("MESHLESS isosurface " + vol + " --iso 50.5 --threads 1 -o " + D + "a.vtp", d).code == 0);
    REQUIRE(sh("MESHLESS isosurface " + vol + " --iso 50.5 --threads 3 -o " + D + "b.VTP --png " + D + "b.png --size 64x64", d).code == 0);
    // the pipe path and stdout
    REQUIRE(sh("MESHLESS generate " + vol + " --iso 50.5 | MESHLESS project --threads 2 | MESHLESS write -o " + D + "c.vtp", d).code == 0);
    REQUIRE(sh("MESHLESS generate " + vol + " --iso 50.5 | MESHLESS project | MESHLESS write -o - --format vtp > " + D + "d.vtp", d).code == 0);
    REQUIRE(sh("MESHLESS isosurface " + vol + " --iso 50.5 -o " + D + "points.out --format vtp", d).code == 0);
    REQUIRE(sh("MESHLESS isosurface " + vol + " --iso 50.5 -o " + D + "raw.vtp --vtp-compression none", d).code == 0);
    CHECK(sh("MESHLESS isosurface " + vol + " --iso 50.5 -o " + D + "bad.vtp --vtp-compression lz4", d).code == 1);
    CHECK(slurp(d / "raw.vtp").find("compressor=") == std::string::npos);
    const std::string a = slurp(d / "a.vtp");
    CHECK(a.size() > 1000);
    CHECK(a.rfind("<?xml", 0) == 0);
    CHECK(a == slurp(d / "b.VTP"));
    CHECK(a == slurp(d / "points.out"));
    CHECK(slurp(d / "c.vtp") == slurp(d / "d.vtp"));
    CHECK(slurp(d / "c.vtp") == a);  // the same points and provenance lines
    // meshes
    REQUIRE(sh("MESHLESS mc " + vol + " --iso 50.5 --threads 1 -o " + D + "m.ply", d).code == 0);
    REQUIRE(sh("MESHLESS mc " + vol + " --iso 50.5 --threads 1 -o " + D + "m.vtp", d).code == 0);
    REQUIRE(sh("MESHLESS mc " + vol + " --iso 50.5 --threads 2 -o " + D + "m2.vtp", d).code == 0);
    CHECK(slurp(d / "m.vtp") == slurp(d / "m2.vtp"));
    CHECK(slurp(d / "m.vtp").find("<Polys>") != std::string::npos);
    // info says a mesh .vtp is a mesh (its vertices read as points), a point .vtp has no such line
    const auto mi = sh("MESHLESS info " + D + "m.vtp", d);
    REQUIRE(mi.code == 0);
    CHECK_THAT(mi.out, Catch::Contains(" polygons: a surface mesh, read as the points of its vertices"));
    const auto pi = sh("MESHLESS info " + D + "a.vtp", d);
    REQUIRE(pi.code == 0);
    CHECK_THAT(pi.out, !Catch::Contains("polygons"));

    const std::string py = vtk_python(d);
    if (py.empty()) {
        WARN("no python3 imports vtk (python3-vtk9): VTK reader checks skipped");
        return;
    }
    spit(d / "compare.py", kCompare);
    auto r = sh(py + " " + D + "compare.py points " + D + "a.vtp " + D + "a.ply", d);
    INFO(r.err << r.out);
    CHECK(r.code == 0);
    r = sh(py + " " + D + "compare.py points " + D + "raw.vtp " + D + "a.ply", d);
    INFO(r.err << r.out);
    CHECK(r.code == 0);
    r = sh(py + " " + D + "compare.py mesh " + D + "m.vtp " + D + "m.ply", d);
    INFO(r.err << r.out);
    CHECK(r.code == 0);
}

TEST_CASE("vtp: mc on multiblock grids writes the per-cell block array VTK reads", "[cli][vtp][real]") {
    if (!have_shared_data()) {
        WARN("../shared/data absent: multiblock VTP test skipped");
        return;
    }
    TempDir d("vtp-blocks");
    const std::string P = (shared_data() / "plot3d").string() + "/";
    const std::string blocks = P + "multicomb_0.vts " + P + "multicomb_1.vts " + P + "multicomb_2.vts";
    const std::string D = d.path.string() + "/";
    REQUIRE(sh("MESHLESS mc " + blocks + " --iso 0.4 -o " + D + "n.ply", d).code == 0);
    REQUIRE(sh("MESHLESS mc " + blocks + " --iso 0.4 -o " + D + "n.vtp", d).code == 0);
    const std::string v = slurp(d / "n.vtp");
    CHECK(v.find("<CellData Scalars=\"block\">") != std::string::npos);
    CHECK(v.find("<PointData Normals=\"Normals\">") != std::string::npos);  // area-weighted, as the help says
    const std::string py = vtk_python(d);
    if (py.empty()) {
        WARN("no python3 imports vtk (python3-vtk9): VTK reader check skipped");
        return;
    }
    // the PLY of the naive mesh carries the VTP's area-weighted normals (x y z nx ny nz): compare
    // positions, normals, triangles and blocks, and the normals are unit vectors as VTK reads them
    spit(d / "c.py", R"PY(
import sys, numpy as np, vtk
from vtk.util.numpy_support import vtk_to_numpy as v2n
r = vtk.vtkXMLPolyDataReader(); r.SetFileName(sys.argv[1]); r.Update(); p = r.GetOutput()
data = open(sys.argv[2], "rb").read(); end = data.index(b"end_header\n") + 11
head = data[:end].decode()
c = {l.split()[1]: int(l.split()[2]) for l in head.splitlines() if l.startswith("element")}
props = [l.split()[-1] for l in head.splitlines() if l.startswith("property float")]
if props != ["x", "y", "z", "nx", "ny", "nz"]: sys.exit("vertex properties " + " ".join(props))
nv, nf = c["vertex"], c["face"]
vr = np.frombuffer(data, dtype="<f4", count=6 * nv, offset=end).reshape(nv, 6)
fr = np.frombuffer(data, dtype=np.dtype([("n", "u1"), ("i", "<i4", 3), ("b", "<u4")]), count=nf, offset=end + 24 * nv)
nn = v2n(p.GetPointData().GetNormals()) if p.GetPointData().GetNormals() is not None else None
ok = (p.GetNumberOfPoints() == nv and p.GetNumberOfPolys() == nf and np.array_equal(v2n(p.GetPoints().GetData()), vr[:, :3])
      and nn is not None and np.array_equal(nn, vr[:, 3:])
      and np.array_equal(v2n(p.GetPolys().GetConnectivityArray()).reshape(nf, 3), fr["i"])
      and np.array_equal(v2n(p.GetCellData().GetArray("block")), fr["b"]) and len(set(fr["b"])) == 3
      and np.abs(np.linalg.norm(nn, axis=1) - 1).max() < 1e-5)
sys.exit(0 if ok else "differs")
)PY");
    const auto r = sh(py + " " + D + "c.py " + D + "n.vtp " + D + "n.ply", d);
    INFO(r.err);
    CHECK(r.code == 0);
}

TEST_CASE("vtp: outputs are chosen by extension or --format, refused commands write nothing", "[cli][vtp]") {
    TempDir d("vtp-choice");
    const std::string vol = write_uint8_analytic_volume(d, "torus", AnalyticField::torus, 16, 200.0, 0.0);
    const std::string D = d.path.string() + "/";
    for (const std::string& bad : {std::string("-o ") + D + "p.xyz", "-o " + D + "p.ply --format vtp",
                                   "-o " + D + "p.out --format obj", "-o " + D + "p.vtp --format ply"}) {
        INFO(bad);
        for (const char* cmd : {"isosurface", "mc"}) {
            const auto r = sh(std::string("MESHLESS ") + cmd + " " + vol + " --iso 50.5 " + bad, d);
            CHECK(r.code == 1);
            CHECK(r.err.find("meshless") != std::string::npos);
            CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
        }
    }
    const auto r = sh("MESHLESS isosurface " + vol + " --iso 50.5 -o " + D + "p.xyz", d);
    CHECK(r.err.find(".vtp") != std::string::npos);  // the message names the formats it writes
    // only the volume and the captured streams are in the directory
    for (const auto& e : std::filesystem::directory_iterator(d.path)) {
        const std::string n = e.path().filename().string();
        CHECK((n.find(".raw") != std::string::npos || n == "stderr.txt" || n == "stdout.txt"));
    }
    // stdout without --format stays PLY (what pipes always got)
    REQUIRE(sh("MESHLESS isosurface " + vol + " --iso 50.5 -o - > " + D + "s.out", d).code == 0);
    CHECK(slurp(d / "s.out").rfind("ply\n", 0) == 0);
}

TEST_CASE("ply-color: red green blue per point (normal, value, block), kept by vtkPLYReader", "[cli][vtp]") {
    TempDir d("ply-color");
    const std::string vol = write_uint8_analytic_volume(d, "torus", AnalyticField::torus, 32, 200.0, 0.0);
    const std::string D = d.path.string() + "/";
    REQUIRE(sh("MESHLESS isosurface " + vol + " --iso 50.5 -o " + D + "plain.ply", d).code == 0);
    REQUIRE(sh("MESHLESS isosurface " + vol + " --iso 50.5 --ply-color normal -o " + D + "n.ply", d).code == 0);
    // the same points, colours from the normals: (n + 1) / 2 * 255
    PlyReader plain(D + "plain.ply"), col(D + "n.ply");
    const PlyElement& ve = col.header().elements[0];
    REQUIRE(ve.find("red") == 8);
    REQUIRE(ve.find("blue") == 10);
    std::vector<double> a, b;
    const std::size_t n = plain.read_values(a, 1u << 20);
    REQUIRE(col.read_values(b, 1u << 20) == n);
    REQUIRE(n > 100);
    for (std::size_t i = 0; i < n; i += 7) {
        for (int c = 0; c < 8; ++c) REQUIRE(b[i * 11 + c] == a[i * 8 + c]);
        for (int c = 0; c < 3; ++c) REQUIRE(std::abs(b[i * 11 + 8 + c] - (a[i * 8 + 3 + c] + 1) * 127.5) <= 1.0);
    }
    // the pipe's writer, by value over --range; stdout holds the points until the end
    REQUIRE(sh("MESHLESS generate " + vol + " --iso 50.5 | MESHLESS project | MESHLESS write --ply-color value --range 0,101 -o " +
                   D + "v.ply", d).code == 0);
    REQUIRE(sh("MESHLESS generate " + vol + " --iso 50.5 | MESHLESS project | MESHLESS write --ply-color value --range 0,101 -o - > " +
                   D + "v2.ply", d).code == 0);
    CHECK(slurp(d / "v.ply") == slurp(d / "v2.ply"));
    PlyReader v(D + "v.ply");
    std::vector<double> c;
    REQUIRE(v.read_values(c, 1) == 1);
    const auto want = map_color(Colormap::viridis, 50.5, 0, 101);
    CHECK(c[8] == want[0]);
    CHECK(c[9] == want[1]);
    CHECK(c[10] == want[2]);
    CHECK(sh("MESHLESS isosurface " + vol + " --iso 50.5 --ply-color normal -o " + D + "x.vtp", d).code == 1);
    CHECK(sh("MESHLESS isosurface " + vol + " --iso 50.5 --ply-color rainbow -o " + D + "x.ply", d).code == 1);
    const std::string py = vtk_python(d);
    if (py.empty()) {
        WARN("no python3 imports vtk (python3-vtk9): vtkPLYReader check skipped");
        return;
    }
    const auto r = sh(py + " -c \"import vtk; r = vtk.vtkPLYReader(); r.SetFileName(\\\"" + D +
                          "n.ply\\\"); r.Update(); a = r.GetOutput().GetPointData().GetArray(\\\"RGB\\\"); "
                          "print(a.GetNumberOfTuples(), a.GetNumberOfComponents())\"", d);
    INFO(r.err);
    CHECK(r.out == std::to_string(n) + " 3\n");
}

TEST_CASE("splat of a .vtp of oriented points draws the picture of the same points' PLY", "[cli][vtp][splat]") {
    TempDir d("vtp-splat");
    const std::string D = d.path.string() + "/";
    const std::string vol = write_uint8_analytic_volume(d, "vol", AnalyticField::torus, 24, 200.0, 0.0);
    REQUIRE(sh("MESHLESS isosurface " + vol + " --iso 100.5 -o " + D + "p.ply", d).code == 0);
    REQUIRE(sh("MESHLESS isosurface " + vol + " --iso 100.5 -o " + D + "p.vtp", d).code == 0);
    REQUIRE(sh("MESHLESS isosurface " + vol + " --iso 100.5 -o " + D + "raw.vtp --vtp-compression none", d).code == 0);
    for (const char* opts : {"", " --kernel ewa", " --color normal --azimuth 40"}) {
        INFO(opts);
        REQUIRE(sh("MESHLESS splat " + D + "p.ply -o " + D + "from_ply.png" + opts, d).code == 0);
        REQUIRE(sh("MESHLESS splat " + D + "p.vtp -o " + D + "from_vtp.png" + opts, d).code == 0);
        REQUIRE(sh("MESHLESS splat " + D + "raw.vtp -o " + D + "from_raw.png" + opts, d).code == 0);
        CHECK(slurp(d / "from_ply.png") == slurp(d / "from_vtp.png"));
        CHECK(slurp(d / "from_ply.png") == slurp(d / "from_raw.png"));
    }
    // a mesh, and points without normals (a level of detail's), are refused with what to do
    REQUIRE(sh("MESHLESS mc " + vol + " --iso 100.5 -o " + D + "m.vtp", d).code == 0);
    auto r = sh("MESHLESS splat " + D + "m.vtp -o " + D + "x.png", d);
    CHECK(r.code == 2);
    CHECK_THAT(r.err, Catch::Contains("m.vtp: piece 0 is a surface mesh"));
    REQUIRE(sh("MESHLESS sample " + vol + " --count 500 -o " + D + "s.vtp", d).code == 0);
    r = sh("MESHLESS splat " + D + "s.vtp -o " + D + "x.png", d);
    CHECK(r.code == 2);
    CHECK_THAT(r.err, Catch::Contains("s.vtp: piece 0: splat draws oriented points"));
    CHECK_FALSE(std::filesystem::exists(d / "x.png"));
    r = sh("MESHLESS splat " + D + "p.vtp --iso 3 -o " + D + "x.png", d);
    CHECK(r.code == 1);
}
