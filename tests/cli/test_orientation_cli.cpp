// Orientation like VTK end to end: `meshless mc` and `meshless isosurface` against
//   - VTK itself (python3-vtk9 under /usr/bin/python3; skipped with a warning when it does not import
//     vtk): vtkFlyingEdges3D with ComputeNormals on the same small uint8 volume (a ball with high
//     values inside, and its complement, high values outside): our point normals and mesh vertex
//     normals point the same way as VTK's normal at the nearest VTK vertex, and our mesh's signed
//     volume has the sign of VTK's (a signed-volume sum over VTK's triangles);
//   - real data: `mc sphere.slc --iso 128` encloses positive signed volume (high values inside, so
//     triangles facing outwards; -22,209 before the convention changed), and the iso-splatted
//     points' normals point away from the object's centre.
#include <catch2/catch.hpp>

#include <filesystem>
#include <sstream>

#include "cli/cli_harness.hpp"
#include "formats/ply_mesh.hpp"
#include "formats/ply_points.hpp"

using namespace meshless;
using namespace meshless::test;

namespace {

double signed_volume(const Mesh& m) {
    double v = 0;
    for (std::size_t t = 0; t < m.triangle_count(); ++t) {
        Vec3 p[3];
        for (int q = 0; q < 3; ++q) {
            const float* x = &m.xyz[3 * m.tri[3 * t + static_cast<std::size_t>(q)]];
            p[q] = {x[0], x[1], x[2]};
        }
        v += dot(p[0], cross(p[1], p[2])) / 6;
    }
    return v;
}

// argv: volume.raw n iso ours_mesh.ply ours_points.ply. vtkFlyingEdges3D (ComputeNormals on) on the
// uint8 volume (origin 0, spacing 1, as meshless reads a raw volume named NAME_NxNxN_uint8.raw);
// our PLYs through vtkPLYReader (it keeps x y z, normals and faces). Prints: VTK's signed volume,
// ours, then for our mesh vertices and our points: the fraction whose normal has a positive dot
// with VTK's normal at the nearest VTK vertex, and the largest distance to that vertex.
const char* kVtkOrientation = R"PY(
import sys, numpy as np, vtk
from vtk.util.numpy_support import vtk_to_numpy as v2n, numpy_to_vtk as n2v
raw, n, iso, mesh_ply, points_ply = sys.argv[1], int(sys.argv[2]), float(sys.argv[3]), sys.argv[4], sys.argv[5]
img = vtk.vtkImageData(); img.SetDimensions(n, n, n); img.SetOrigin(0, 0, 0); img.SetSpacing(1, 1, 1)
img.GetPointData().SetScalars(n2v(np.fromfile(raw, dtype=np.uint8), deep=1, array_type=vtk.VTK_UNSIGNED_CHAR))
fe = vtk.vtkFlyingEdges3D(); fe.SetInputData(img); fe.SetValue(0, iso); fe.ComputeNormalsOn(); fe.Update()
out = fe.GetOutput()
def volume(pd):
    x = v2n(pd.GetPoints().GetData()).astype(np.float64)
    t = v2n(pd.GetPolys().GetConnectivityArray()).reshape(-1, 3)
    return float(np.einsum("ij,ij->i", x[t[:, 0]], np.cross(x[t[:, 1]], x[t[:, 2]])).sum() / 6)
loc = vtk.vtkStaticPointLocator(); loc.SetDataSet(out); loc.BuildLocator()
vx = v2n(out.GetPoints().GetData()); vn = v2n(out.GetPointData().GetNormals())
def agree(pd):
    x = v2n(pd.GetPoints().GetData()); nn = v2n(pd.GetPointData().GetNormals())
    ids = np.array([loc.FindClosestPoint(p) for p in x])
    return float((np.einsum("ij,ij->i", nn, vn[ids]) > 0).mean()), float(np.linalg.norm(x - vx[ids], axis=1).max())
def read(path):
    r = vtk.vtkPLYReader(); r.SetFileName(path); r.Update(); return r.GetOutput()
mesh, pts = read(mesh_ply), read(points_ply)
print(volume(out), volume(mesh), *agree(mesh), *agree(pts))
)PY";

}  // namespace

TEST_CASE("orientation: normals and mc winding agree with vtkFlyingEdges3D on a ball and its complement", "[cli][vtk][orientation]") {
    TempDir d("orient-vtk");
    if (sh("/usr/bin/python3 -c \"import vtk, numpy\"", d).code != 0) {
        WARN("/usr/bin/python3 does not import vtk (python3-vtk9): VTK orientation check skipped");
        return;
    }
    spit(d / "vtk_orientation.py", kVtkOrientation);
    const std::string D = d.path.string() + "/";
    const int n = 33;
    // value = round(|p| * scale + offset) over [-1, 1]^3: scale < 0 puts the high values inside
    struct Case { const char* name; double scale, offset; };
    for (const Case c : {Case{"ball", -200.0, 220.0}, Case{"hollow", 200.0, 0.0}}) {
        INFO(c.name);
        const std::string vol = write_uint8_analytic_volume(d, c.name, AnalyticField::sphere, n, c.scale, c.offset);
        REQUIRE(sh("MESHLESS mc " + vol + " --iso 100.5 -o " + D + "m.ply", d).code == 0);
        REQUIRE(sh("MESHLESS isosurface " + vol + " --iso 100.5 -o " + D + "p.ply", d).code == 0);
        const auto r = sh("/usr/bin/python3 " + D + "vtk_orientation.py " + vol + " " + std::to_string(n) + " 100.5 " + D + "m.ply " +
                              D + "p.ply",
                          d);
        INFO(r.err << r.out);
        REQUIRE(r.code == 0);
        std::istringstream in(r.out);
        double vtk_volume = 0, vtk_ours = 0, mesh_agree = 0, mesh_dist = 0, pts_agree = 0, pts_dist = 0;
        in >> vtk_volume >> vtk_ours >> mesh_agree >> mesh_dist >> pts_agree >> pts_dist;
        REQUIRE(in);
        const double ours = signed_volume(read_ply_mesh(D + "m.ply"));
        CHECK(ours == Approx(vtk_ours).epsilon(1e-6));  // the PLY VTK read is the mesh we read
        CHECK(std::abs(vtk_volume) > 1000);              // a ball of radius ~ 9.5 voxels
        CHECK((ours > 0) == (vtk_volume > 0));
        CHECK((ours > 0) == (c.scale < 0));  // positive around high values
        CHECK(ours == Approx(vtk_volume).epsilon(0.02));
        CHECK(mesh_agree == 1.0);
        CHECK(mesh_dist < 1.0);  // voxels: the same grid, the same surface
        CHECK(pts_agree == 1.0);
        CHECK(pts_dist < 1.0);
    }
}

TEST_CASE("orientation: mc on sphere.slc encloses positive volume, points face outwards", "[cli][real][orientation]") {
    if (!have_shared_data()) {
        WARN("../shared/data not found: sphere.slc orientation check skipped");
        return;
    }
    TempDir d("orient-slc");
    const std::string D = d.path.string() + "/", V = (shared_data() / "vtk_slc/sphere.slc").string();
    REQUIRE(sh("MESHLESS mc " + V + " --iso 128 -o " + D + "m.ply", d).code == 0);
    const Mesh m = read_ply_mesh(D + "m.ply");
    REQUIRE(m.triangle_count() > 1000);
    const double vol = signed_volume(m);
    INFO("signed volume " << vol);
    CHECK(vol > 20000);
    // vertex normals agree with the winding: the area-weighted vertex normals sum to the same volume
    // sign; and the iso-splatted points face away from the centre of the mesh
    Vec3 centre{0, 0, 0};
    for (std::size_t i = 0; i < m.vertex_count(); ++i) centre += Vec3{m.xyz[3 * i], m.xyz[3 * i + 1], m.xyz[3 * i + 2]};
    centre = centre * (1.0 / static_cast<double>(m.vertex_count()));
    std::size_t out = 0;
    for (std::size_t i = 0; i < m.vertex_count(); ++i) {
        const Vec3 x{m.xyz[3 * i], m.xyz[3 * i + 1], m.xyz[3 * i + 2]}, nn{m.normals[3 * i], m.normals[3 * i + 1], m.normals[3 * i + 2]};
        out += dot(nn, x - centre) > 0;
    }
    CHECK(out == m.vertex_count());
    REQUIRE(sh("MESHLESS isosurface " + V + " --iso 128 -o " + D + "p.ply", d).code == 0);
    const PlyPoints pts = read_ply_points(D + "p.ply");
    REQUIRE(pts.points.size() > 1000);
    std::size_t facing = 0;
    for (const PointRecord& p : pts.points)
        facing += dot(Vec3{p.normal[0], p.normal[1], p.normal[2]}, Vec3{p.pos[0], p.pos[1], p.pos[2]} - centre) > 0;
    CHECK(facing == pts.points.size());
}

TEST_CASE("orientation: --azimuth and --elevation turn the face-on view of a volume with patient axes", "[cli][real][orientation]") {
    if (!have_shared_data()) {
        WARN("../shared/data absent: anatomical turn test skipped");
        return;
    }
    // the default turn given explicitly is the default picture (it used to switch the face-on view
    // off and show the generic +y-up one: the head on its side); another turn is another picture
    TempDir d("anatomical_turn");
    const std::string mni = (shared_data() / "mni152_brain" / "avg152T1_RL_nifti.nii.gz").string(), D = d.path.string() + "/";
    const std::string common = " --iso 80.5 -o " + D + "x.ply --size 64x64 --png " + D;
    REQUIRE(sh("MESHLESS isosurface " + mni + common + "default.png", d).code == 0);
    REQUIRE(sh("MESHLESS isosurface " + mni + common + "explicit.png --azimuth 30 --elevation 20", d).code == 0);
    REQUIRE(sh("MESHLESS isosurface " + mni + common + "side.png --azimuth 90 --elevation 0", d).code == 0);
    REQUIRE(sh("MESHLESS isosurface " + mni + common + "generic.png --up +y --azimuth 30 --elevation 20", d).code == 0);
    CHECK(slurp(d / "default.png") == slurp(d / "explicit.png"));
    CHECK(slurp(d / "default.png") != slurp(d / "side.png"));
    CHECK(slurp(d / "default.png") != slurp(d / "generic.png"));  // --up turns the face-on view off
}

TEST_CASE("orientation: --view keeps the header's superior up unless --up is given, a view along the up axis warns", "[cli][real][orientation]") {
    if (!have_shared_data()) {
        WARN("../shared/data absent: --view orientation test skipped");
        return;
    }
    // the headsq CT's superior is -z (NRRD space left-posterior-superior, z slices upwards reversed)
    TempDir d("anatomical_view");
    const std::string head = (shared_data() / "vtk_headsq" / "quarter.nhdr").string(), D = d.path.string() + "/";
    const std::string common = " --tf ct-skin --size 48x48 -o " + D;
    for (const char* v : {"+y", "-x", "iso"}) {
        INFO("--view " << v);
        REQUIRE(sh("MESHLESS render " + head + common + "a.png --view " + v, d).code == 0);
        REQUIRE(sh("MESHLESS render " + head + common + "b.png --view " + v + " --up -z", d).code == 0);
        REQUIRE(sh("MESHLESS render " + head + common + "c.png --view " + v + " --up y", d).code == 0);
        CHECK(slurp(d / "a.png") == slurp(d / "b.png"));  // superior up, as --up's help says
        CHECK(slurp(d / "a.png") != slurp(d / "c.png"));  // (was: --view dropped it for +y up)
    }
    auto r = sh("MESHLESS render " + head + common + "z.png --view +z", d);  // along superior
    CHECK(r.code == 0);
    CHECK_THAT(r.err, Catch::Contains("warning: --view +z looks along the up axis (-z): the picture's up is arbitrary"));
    r = sh("MESHLESS render " + head + common + "y.png --view -y --up y", d);
    CHECK(r.code == 0);
    CHECK_THAT(r.err, Catch::Contains("warning: --view -y looks along the up axis (y)"));
    r = sh("MESHLESS render " + head + common + "ok.png --view -y --up -z", d);
    CHECK(r.err.find("warning") == std::string::npos);
}

TEST_CASE("orientation: splat of an isosurface's PLY or stream faces as isosurface --png does (patient_axes recorded)", "[cli][real][orientation]") {
    if (!have_shared_data()) {
        WARN("../shared/data absent: splat orientation test skipped");
        return;
    }
    // the points carry the volume header's patient axes (PLY comment, stream metadata): splat
    // draws the head up and face-on, as isosurface --png (it drew the headsq CT from below)
    TempDir d("anatomical_splat");
    const std::string head = (shared_data() / "vtk_headsq" / "quarter.nhdr").string(), D = d.path.string() + "/";
    REQUIRE(sh("MESHLESS isosurface " + head + " --iso 1000.5 -o " + D + "h.ply --png " + D + "iso.png --size 64x64", d).code == 0);
    CHECK(slurp(d / "h.ply").find("comment patient_axes 1,0,0,0,1,0,0,0,-1\n") != std::string::npos);
    REQUIRE(sh("MESHLESS splat " + D + "h.ply -o " + D + "ply.png --size 64x64", d).code == 0);
    REQUIRE(sh("MESHLESS generate " + head + " --iso 1000.5 | MESHLESS project | MESHLESS splat -o " + D + "pipe.png --size 64x64", d)
                .code == 0);
    CHECK(slurp(d / "iso.png") == slurp(d / "ply.png"));
    CHECK(slurp(d / "iso.png") == slurp(d / "pipe.png"));
    // --up still chooses the camera, on both
    REQUIRE(sh("MESHLESS splat " + D + "h.ply -o " + D + "up.png --size 64x64 --up y", d).code == 0);
    REQUIRE(sh("MESHLESS isosurface " + head + " --iso 1000.5 --png " + D + "isoup.png --size 64x64 --up y", d).code == 0);
    CHECK(slurp(d / "up.png") != slurp(d / "ply.png"));
    CHECK(slurp(d / "up.png") == slurp(d / "isoup.png"));
}

TEST_CASE("orientation: a brick store keeps its volume's patient axes and gives the volume's pictures", "[cli][real][orientation]") {
    if (!have_shared_data()) {
        WARN("../shared/data absent: brick store orientation test skipped");
        return;
    }
    // VTK's headsq (NRRD, 3D-left-handed: head up means -z up) and the MNI template (NIfTI sform):
    // a store made by convert used to lose the axes, so its pictures showed the head from below
    TempDir d("store_axes");
    const std::string D = d.path.string() + "/";
    for (const auto& [vol, iso] : {std::pair<std::string, std::string>{(shared_data() / "vtk_headsq" / "quarter.nhdr").string(), "500.5"},
                                   {(shared_data() / "mni152_brain" / "avg152T1_RL_nifti.nii.gz").string(), "80.5"}}) {
        INFO(vol);
        REQUIRE(sh("MESHLESS convert " + vol + " -o " + D + "s.mlb", d).code == 0);
        const auto info = sh("MESHLESS info " + D + "s.mlb", d);
        CHECK(info.out.find("patient axes: ") != std::string::npos);
        REQUIRE(sh("MESHLESS isosurface " + vol + " --iso " + iso + " --size 64x64 --png " + D + "v.png", d).code == 0);
        REQUIRE(sh("MESHLESS isosurface " + D + "s.mlb --iso " + iso + " --size 64x64 --png " + D + "s.png", d).code == 0);
        CHECK(slurp(d / "v.png") == slurp(d / "s.png"));
        REQUIRE(sh("MESHLESS render " + vol + " --size 48x48 -o " + D + "rv.png", d).code == 0);
        REQUIRE(sh("MESHLESS render " + D + "s.mlb --size 48x48 -o " + D + "rs.png", d).code == 0);
        CHECK(slurp(d / "rv.png") == slurp(d / "rs.png"));
    }
}
