// Structured multiblock and AMR readers (formats/multiblock_reader.hpp, formats/plot3d.hpp,
// formats/vtk_structured.hpp, formats/vtk_multiblock.hpp): generated files with analytic oracles
// (values are linear functions of the node or cell-centre positions, computed here independently),
// one must-fail test per defect class, and the real multiblock and AMR data of shared/data/SOURCES.md
// sections 2 and 4.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>

#include "error_of.hpp"
#include "formats/multiblock_reader.hpp"
#include "formats/plot3d.hpp"
#include "formats/point_set_reader.hpp"
#include "kernels/errors.hpp"
#include "test_paths.hpp"

using namespace meshless;
using meshless::test::TempDir;

namespace {

using Dims = std::array<std::int64_t, 3>;

double lin(double x, double y, double z) { return 1.5 * x - 2.0 * y + 0.25 * z + 3.0; }

std::string P(const TempDir& d, const std::string& n) { return (d / n).string(); }

void spit(const std::string& p, const std::string& s) {
    std::ofstream f(p, std::ios::binary);
    f << s;
}

std::string slurp(const std::string& p) {
    std::ifstream f(p, std::ios::binary);
    std::stringstream ss;
    ss << f.rdbuf();
    return ss.str();
}

template <class F>
std::string error_of(F&& f) {
    return test::error_of<FormatError, IoError>(f);
}

std::string nums(const std::vector<double>& v) {
    std::ostringstream s;
    s.precision(17);
    for (double x : v) s << x << ' ';
    return s.str();
}

// --- VTK XML writers (ascii payloads) ----------------------------------------------------------

struct Arr {
    std::string name;
    std::vector<double> v;
    int comps = 1;
    bool cell = false;
};

std::string data_sections(const std::vector<Arr>& arrays) {
    std::string pd = "<PointData>\n", cd = "<CellData>\n";
    for (const auto& a : arrays) {
        std::string s = "<DataArray type=\"Float64\" Name=\"" + a.name + "\" NumberOfComponents=\"" + std::to_string(a.comps) +
                        "\" format=\"ascii\">" + nums(a.v) + "</DataArray>\n";
        (a.cell ? cd : pd) += s;
    }
    return pd + "</PointData>\n" + cd + "</CellData>\n";
}

std::string ext_text(const std::array<std::int64_t, 6>& e) {
    std::string s;
    for (auto x : e) s += std::to_string(x) + " ";
    return s;
}

void write_vti(const std::string& path, std::array<std::int64_t, 6> ext, std::array<double, 3> origin,
               std::array<double, 3> spacing, const std::vector<Arr>& arrays) {
    std::ostringstream s;
    s.precision(17);
    s << "<?xml version=\"1.0\"?>\n<VTKFile type=\"ImageData\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
      << "<ImageData WholeExtent=\"" << ext_text(ext) << "\" Origin=\"" << origin[0] << " " << origin[1] << " " << origin[2]
      << "\" Spacing=\"" << spacing[0] << " " << spacing[1] << " " << spacing[2] << "\">\n<Piece Extent=\"" << ext_text(ext)
      << "\">\n"
      << data_sections(arrays) << "</Piece>\n</ImageData>\n</VTKFile>\n";
    spit(path, s.str());
}

// A curvilinear block: node(i,j,k) = sheared, rotated lattice; point data "f" = lin(node).
Vec3 curv_node(int i, int j, int k) { return Vec3{0.5 * i + 0.1 * j, 0.4 * j + 0.05 * k * k, 0.3 * k + 0.02 * i * j}; }

void write_vts(const std::string& path, Dims d, const std::vector<Arr>& arrays, bool nan_node = false) {
    std::vector<double> pts;
    for (int k = 0; k < d[2]; ++k)
        for (int j = 0; j < d[1]; ++j)
            for (int i = 0; i < d[0]; ++i) {
                const Vec3 p = curv_node(i, j, k);
                pts.insert(pts.end(), {p.x, p.y, p.z});
            }
    std::string ptext = nums(pts);
    if (nan_node) ptext = "nan " + ptext.substr(ptext.find(' ') + 1);
    const std::string e = "0 " + std::to_string(d[0] - 1) + " 0 " + std::to_string(d[1] - 1) + " 0 " + std::to_string(d[2] - 1);
    spit(path, "<VTKFile type=\"StructuredGrid\" version=\"0.1\">\n<StructuredGrid WholeExtent=\"" + e + "\">\n<Piece Extent=\"" + e +
                   "\">\n" + data_sections(arrays) + "<Points><DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">" +
                   ptext + "</DataArray></Points>\n</Piece>\n</StructuredGrid>\n</VTKFile>\n");
}

Arr curv_point_field(Dims d) {
    Arr a{"f", {}};
    for (int k = 0; k < d[2]; ++k)
        for (int j = 0; j < d[1]; ++j)
            for (int i = 0; i < d[0]; ++i) {
                const Vec3 p = curv_node(i, j, k);
                a.v.push_back(lin(p.x, p.y, p.z));
            }
    return a;
}

// Cell values of a box: lin at the cell centre origin + (lo + i + 0.5) h.
Arr box_cell_field(const std::string& name, std::array<std::int64_t, 3> cells, std::array<double, 3> piece_origin,
                   std::array<double, 3> h) {
    Arr a{name, {}, 1, true};
    for (int k = 0; k < cells[2]; ++k)
        for (int j = 0; j < cells[1]; ++j)
            for (int i = 0; i < cells[0]; ++i)
                a.v.push_back(lin(piece_origin[0] + (i + 0.5) * h[0], piece_origin[1] + (j + 0.5) * h[1],
                                  piece_origin[2] + (k + 0.5) * h[2]));
    return a;
}

// A two-level hierarchy over [0,4]^3: level 0 one box of 4^3 cells (h 1), level 1 two boxes of 4^3
// cells (h 0.5) at cell index 2..5 and 2..5 x 2..5 x 6..7 -> origins (1,1,1), (1,1,3).
struct AmrBox {
    int level;
    std::array<std::int64_t, 6> box;
    std::string file;
};
std::vector<AmrBox> amr_boxes() {
    return {{0, {0, 3, 0, 3, 0, 3}, "p0.vti"}, {1, {2, 5, 2, 5, 2, 5}, "p1.vti"}, {1, {2, 5, 2, 5, 6, 7}, "p2.vti"}};
}

void write_amr_pieces(const TempDir& d, bool point_data_in_last = false) {
    for (const auto& b : amr_boxes()) {
        const double h = b.level == 0 ? 1.0 : 0.5;
        const std::array<std::int64_t, 3> cells{b.box[1] - b.box[0] + 1, b.box[3] - b.box[2] + 1, b.box[5] - b.box[4] + 1};
        const std::array<double, 3> org{b.box[0] * h, b.box[2] * h, b.box[4] * h};
        std::vector<Arr> arrays{box_cell_field("vel", cells, org, {h, h, h}), box_cell_field("rho", cells, org, {h, h, h})};
        arrays[0].comps = 3;
        arrays[0].v.resize(3 * arrays[0].v.size(), 0.5);
        if (point_data_in_last && b.file == "p2.vti") arrays[1] = Arr{"rho", std::vector<double>(5 * 5 * 3, 1.0), 1, false};
        write_vti(P(d, b.file), {0, cells[0], 0, cells[1], 0, cells[2]}, org, {h, h, h}, arrays);
    }
}

std::string vthb_text(const std::vector<AmrBox>& boxes) {
    std::string s = "<VTKFile type=\"vtkOverlappingAMR\" version=\"1.1\" byte_order=\"LittleEndian\">\n"
                    "<vtkOverlappingAMR origin=\"0 0 0\" grid_description=\"XYZ\">\n";
    for (int level = 0; level < 2; ++level) {
        s += level == 0 ? "<Block level=\"0\" spacing=\"1 1 1\">\n" : "<Block level=\"1\" spacing=\"0.5 0.5 0.5\">\n";
        int index = 0;
        for (const auto& b : boxes)
            if (b.level == level)
                s += "<DataSet index=\"" + std::to_string(index++) + "\" amr_box=\"" + ext_text(b.box) + "\" file=\"" + b.file + "\"/>\n";
        s += "</Block>\n";
    }
    return s + "</vtkOverlappingAMR>\n</VTKFile>\n";
}

std::string amr_vtm_text(const std::vector<AmrBox>& boxes, int ratio = 2) {
    std::string s = "<?xml version=\"1.0\"?>\n<VTKFile type=\"vtkHierarchicalBoxDataSet\" version=\"0.1\">\n"
                    "<vtkHierarchicalBoxDataSet>\n<RefinementRatio level=\"0\" refinement=\"" + std::to_string(ratio) + "\"/>\n";
    int index = 0;
    for (const auto& b : boxes)
        s += "<DataSet group=\"" + std::to_string(b.level) + "\" dataset=\"" + std::to_string(index++) + "\" amr_box=\"" +
             ext_text(b.box) + "\" file=\"" + b.file + "\"/>\n";
    return s + "</vtkHierarchicalBoxDataSet>\n</VTKFile>\n";
}

// Every node of a cell-centred AMR block: at its cell centre, with the value of the oracle there.
void check_amr(const Multiblock& mb) {
    REQUIRE(mb.blocks.size() == 3);
    CHECK(mb.value_name == "rho");
    const auto boxes = amr_boxes();
    for (std::size_t b = 0; b < 3; ++b) {
        const StructuredBlock& blk = mb.blocks[b];
        const double h = boxes[b].level == 0 ? 1.0 : 0.5;
        CHECK(blk.level == boxes[b].level);
        CHECK(blk.cell_centred);
        CHECK(blk.dims == Dims{boxes[b].box[1] - boxes[b].box[0] + 1, boxes[b].box[3] - boxes[b].box[2] + 1,
                               boxes[b].box[5] - boxes[b].box[4] + 1});
        for (std::int64_t k = 0; k < blk.dims[2]; ++k)
            for (std::int64_t j = 0; j < blk.dims[1]; ++j)
                for (std::int64_t i = 0; i < blk.dims[0]; ++i) {
                    const Vec3 want{(boxes[b].box[0] + i + 0.5) * h, (boxes[b].box[2] + j + 0.5) * h, (boxes[b].box[4] + k + 0.5) * h};
                    const std::size_t n = static_cast<std::size_t>(blk.index(i, j, k));
                    REQUIRE(blk.node[n].x == Approx(want.x).margin(1e-12));
                    REQUIRE(blk.node[n].y == Approx(want.y).margin(1e-12));
                    REQUIRE(blk.node[n].z == Approx(want.z).margin(1e-12));
                    REQUIRE(blk.value[n] == Approx(lin(want.x, want.y, want.z)).margin(1e-12));
                }
    }
}

// --- PLOT3D writer: single grid, big-endian float32, C layout -----------------------------------

void put32(std::string& s, std::uint32_t u) {
    for (int b = 3; b >= 0; --b) s.push_back(static_cast<char>((u >> (8 * b)) & 0xff));
}
void putf(std::string& s, float f) {
    std::uint32_t u;
    std::memcpy(&u, &f, 4);
    put32(s, u);
}

// xyz (+IBLANK: `blank(n)` true -> 0) and q with rho = lin(node); dims of the q file may differ.
template <class Blank>
void write_plot3d(const std::string& xyz, const std::string& q, Dims d, Blank blank, bool iblank, Dims qd, float nan_at = -1) {
    std::string x, qq;
    for (auto v : d) put32(x, static_cast<std::uint32_t>(v));
    const std::int64_t N = d[0] * d[1] * d[2];
    std::vector<Vec3> p;
    for (int k = 0; k < d[2]; ++k)
        for (int j = 0; j < d[1]; ++j)
            for (int i = 0; i < d[0]; ++i) p.push_back(curv_node(i, j, k));
    for (std::int64_t n = 0; n < N; ++n) putf(x, n == nan_at ? std::nanf("") : static_cast<float>(p[n].x));
    for (std::int64_t n = 0; n < N; ++n) putf(x, static_cast<float>(p[n].y));
    for (std::int64_t n = 0; n < N; ++n) putf(x, static_cast<float>(p[n].z));
    if (iblank)
        for (std::int64_t n = 0; n < N; ++n) put32(x, blank(n) ? 0u : 1u);
    spit(xyz, x);
    for (auto v : qd) put32(qq, static_cast<std::uint32_t>(v));
    for (float v : {0.5f, 0.f, 1e6f, 0.f}) putf(qq, v);
    const std::int64_t QN = qd[0] * qd[1] * qd[2];
    for (int c = 0; c < 5; ++c)
        for (std::int64_t n = 0; n < QN; ++n) {
            const Vec3 v = n < N ? p[n] : Vec3{0, 0, 0};
            putf(qq, c == 0 ? static_cast<float>(lin(v.x, v.y, v.z)) : 1.0f);
        }
    spit(q, qq);
}

std::string R(const std::string& rel) { return (meshless::test::shared_data() / rel).string(); }

}  // namespace

// ------------------------------------------------------------------------------------- PLOT3D

TEST_CASE("PLOT3D blocks: IBLANK 0 and NaN nodes stay in the lattice, marked invalid and counted", "[multiblock]") {
    TempDir d("mb-p3d");
    const Dims dims{4, 3, 5};
    write_plot3d(P(d, "gxyz.bin"), P(d, "gq.bin"), dims, [](std::int64_t n) { return n % 7 == 3; }, true, dims, 11);
    const Multiblock mb = read_multiblock({P(d, "gxyz.bin")});
    REQUIRE(mb.blocks.size() == 1);
    const StructuredBlock& b = mb.blocks[0];
    CHECK(mb.format == "plot3d");
    CHECK(mb.value_name == "density");
    CHECK(b.dims == dims);
    REQUIRE(b.node.size() == 60);
    REQUIRE(b.valid.size() == 60);
    std::uint64_t blanked = 0;
    for (int k = 0, n = 0; k < dims[2]; ++k)
        for (int j = 0; j < dims[1]; ++j)
            for (int i = 0; i < dims[0]; ++i, ++n) {
                const Vec3 e = curv_node(i, j, k);
                const bool bl = n % 7 == 3;
                blanked += bl;
                CHECK(b.is_valid(n) == (!bl && n != 11));
                if (n == 11) continue;  // NaN x
                CHECK(b.node[n].x == Approx(e.x).margin(1e-6));
                CHECK(b.node[n].z == Approx(e.z).margin(1e-6));
                CHECK(b.value[n] == Approx(lin(e.x, e.y, e.z)).epsilon(1e-6));
            }
    CHECK(mb.blanked == blanked);
    CHECK(mb.nonfinite == 1);
    // the point-set reader (same parse) drops exactly these nodes
    const PointSet ps = read_point_set(P(d, "gxyz.bin"));
    CHECK(ps.dropped_blanked == mb.blanked);
    CHECK(ps.dropped_nonfinite == mb.nonfinite);
    const PointSet again = to_point_set(mb);
    REQUIRE(again.size() == ps.size());
    for (std::size_t i = 0; i < ps.size(); ++i) {
        CHECK(again.pos[i].x == ps.pos[i].x);
        CHECK(again.value[i] == ps.value[i]);
    }
    // strict: the NaN coordinate is refused with the grid and point
    PointSetOptions strict;
    strict.strict = true;
    CHECK_THAT(error_of([&] { read_multiblock({P(d, "gxyz.bin")}, strict); }),
               Catch::Contains("gxyz.bin: grid 1 point 11: non-finite coordinate"));
}

TEST_CASE("PLOT3D blocks: bad input (q/xyz dims disagree, every node blanked, no values)", "[multiblock]") {
    TempDir d("mb-p3d-bad");
    write_plot3d(P(d, "axyz.bin"), P(d, "aq.bin"), {4, 3, 2}, [](std::int64_t) { return false; }, false, {4, 2, 3});
    CHECK_THAT(error_of([&] { read_multiblock({P(d, "axyz.bin")}); }),
               Catch::Contains("aq.bin: PLOT3D q dims 4x2x3 disagree with the xyz dims 4x3x2"));
    write_plot3d(P(d, "bxyz.bin"), P(d, "bq.bin"), {4, 3, 2}, [](std::int64_t) { return true; }, true, {4, 3, 2});
    CHECK_THAT(error_of([&] { read_multiblock({P(d, "bxyz.bin")}); }),
               Catch::Contains("bxyz.bin: grid 1 (4x3x2): every node is blanked"));
    write_plot3d(P(d, "c.xyz"), P(d, "unused.q"), {4, 3, 2}, [](std::int64_t) { return false; }, false, {4, 3, 2});
    CHECK_THAT(error_of([&] { read_multiblock({P(d, "c.xyz")}); }), Catch::Contains("c.xyz: no values"));
    // dims whose product wraps around 2^64 (2^21 * 2^21 * 2^22): no layout, not an empty grid
    spit(P(d, "wrap.xyz"), "2097152 2097152 4194304\n");
    CHECK_THAT(error_of([&] { read_multiblock({P(d, "wrap.xyz")}); }), Catch::Contains("wrap.xyz: not a PLOT3D xyz file: no layout"));
}

// ------------------------------------------------------------------------------------- VTK XML

TEST_CASE("VTS blocks: point data as nodes, cell data as cell centres (mean of the 8 corners)", "[multiblock]") {
    TempDir d("mb-vts");
    const Dims dims{4, 3, 5};
    Arr cellf{"c", {}, 1, true};
    std::vector<Vec3> centres;
    for (int k = 0; k < 4; ++k)
        for (int j = 0; j < 2; ++j)
            for (int i = 0; i < 3; ++i) {
                Vec3 c{0, 0, 0};
                for (int dk = 0; dk < 2; ++dk)
                    for (int dj = 0; dj < 2; ++dj)
                        for (int di = 0; di < 2; ++di) {
                            const Vec3 p = curv_node(i + di, j + dj, k + dk);
                            c = Vec3{c.x + p.x / 8, c.y + p.y / 8, c.z + p.z / 8};
                        }
                centres.push_back(c);
                cellf.v.push_back(lin(c.x, c.y, c.z));
            }
    Arr vec{"v", std::vector<double>(3 * 60, 1.0), 3};
    write_vts(P(d, "g.vts"), dims, {vec, curv_point_field(dims), cellf});
    const Multiblock pm = read_multiblock({P(d, "g.vts")});  // default: the first scalar point array
    REQUIRE(pm.blocks.size() == 1);
    CHECK(pm.value_name == "f");
    CHECK_FALSE(pm.blocks[0].cell_centred);
    CHECK(pm.blocks[0].dims == dims);
    for (int k = 0, n = 0; k < dims[2]; ++k)
        for (int j = 0; j < dims[1]; ++j)
            for (int i = 0; i < dims[0]; ++i, ++n) {
                const Vec3 e = curv_node(i, j, k);
                CHECK(pm.blocks[0].node[n].y == e.y);
                CHECK(pm.blocks[0].value[n] == Approx(lin(e.x, e.y, e.z)).margin(1e-12));
            }
    PointSetOptions o;
    o.value_name = "c";
    const Multiblock cm = read_multiblock({P(d, "g.vts")}, o);
    REQUIRE(cm.blocks.size() == 1);
    const StructuredBlock& b = cm.blocks[0];
    CHECK(b.cell_centred);
    CHECK(b.dims == Dims{3, 2, 4});
    REQUIRE(b.node.size() == centres.size());
    for (std::size_t n = 0; n < centres.size(); ++n) {
        CHECK(b.node[n].x == Approx(centres[n].x).margin(1e-12));
        CHECK(b.node[n].z == Approx(centres[n].z).margin(1e-12));
        CHECK(b.value[n] == Approx(lin(b.node[n].x, b.node[n].y, b.node[n].z)).margin(1e-12));
    }
    // a vector array by name is refused with the list of scalar arrays
    o.value_name = "v";
    const std::string msg = error_of([&] { read_multiblock({P(d, "g.vts")}, o); });
    CHECK_THAT(msg, Catch::Contains("g.vts: piece 0: array 'v' has 3 components"));
    CHECK_THAT(msg, Catch::Contains("'f' (point), 'c' (cell)"));
    o.value_name = "nope";
    CHECK_THAT(error_of([&] { read_multiblock({P(d, "g.vts")}, o); }), Catch::Contains("no PointData or CellData array 'nope'"));
    // NaN coordinate: marked invalid and counted, refused in strict mode with the piece and point
    write_vts(P(d, "n.vts"), dims, {curv_point_field(dims)}, true);
    const Multiblock nm = read_multiblock({P(d, "n.vts")});
    CHECK(nm.nonfinite == 1);
    CHECK_FALSE(nm.blocks[0].is_valid(0));
    CHECK(nm.blocks[0].is_valid(1));
    PointSetOptions strict;
    strict.strict = true;
    CHECK_THAT(error_of([&] { read_multiblock({P(d, "n.vts")}, strict); }),
               Catch::Contains("n.vts: piece 0 point 0: non-finite coordinate"));
    // a vtkGhostType point array blanks the HIDDENPOINT (0x02) points, not the DUPLICATEPOINT (0x01) ones
    Arr ghost{"vtkGhostType", std::vector<double>(60, 0.0)};
    ghost.v[5] = 2, ghost.v[6] = 1, ghost.v[7] = 3;
    write_vts(P(d, "h.vts"), dims, {ghost, curv_point_field(dims)});
    const Multiblock hm = read_multiblock({P(d, "h.vts")});
    CHECK(hm.value_name == "f");  // never the ghost array by default
    CHECK(hm.blanked == 2);
    CHECK_FALSE(hm.blocks[0].is_valid(5));
    CHECK(hm.blocks[0].is_valid(6));
    CHECK_FALSE(hm.blocks[0].is_valid(7));
    // several files: several blocks, named by file
    const Multiblock two = read_multiblock({P(d, "g.vts"), P(d, "n.vts")});
    REQUIRE(two.blocks.size() == 2);
    CHECK(two.blocks[1].name == "n.vts");
}

TEST_CASE("VTR and VTI pieces in a .vtm become blocks with their node positions", "[multiblock]") {
    TempDir d("mb-vtm");
    // rectilinear: x {0, 1, 3}, y {0, 2}, z {-1, 0, 1, 5}
    const std::vector<double> xs{0, 1, 3}, ys{0, 2}, zs{-1, 0, 1, 5};
    Arr f{"f", {}};
    for (double z : zs)
        for (double y : ys)
            for (double x : xs) f.v.push_back(lin(x, y, z));
    spit(P(d, "r.vtr"), "<VTKFile type=\"RectilinearGrid\"><RectilinearGrid WholeExtent=\"0 2 0 1 0 3\"><Piece Extent=\"0 2 0 1 0 3\">" +
                            data_sections({f}) + "<Coordinates><DataArray type=\"Float64\" format=\"ascii\">" + nums(xs) +
                            "</DataArray><DataArray type=\"Float64\" format=\"ascii\">" + nums(ys) +
                            "</DataArray><DataArray type=\"Float64\" format=\"ascii\">" + nums(zs) +
                            "</DataArray></Coordinates></Piece></RectilinearGrid></VTKFile>");
    std::filesystem::create_directories(d / "sub");
    Arr g{"f", {}};
    for (int k = 0; k < 2; ++k)
        for (int j = 0; j < 2; ++j)
            for (int i = 0; i < 3; ++i) g.v.push_back(lin(10 + 0.5 * (1 + i), 0.25 * (2 + j), -2 + k));
    write_vti(P(d, "sub/i.vti"), {1, 3, 2, 3, 0, 1}, {10, 0, -2}, {0.5, 0.25, 1}, {g});
    spit(P(d, "m.vtm"), "<VTKFile type=\"vtkMultiBlockDataSet\" version=\"1.0\">\n<vtkMultiBlockDataSet>\n"
                        "<Block index=\"0\" name=\"outer\"><DataSet index=\"0\" name=\"rect\" file=\"r.vtr\"/>\n"
                        "<Block index=\"1\"><DataSet index=\"0\" file=\"sub/i.vti\"/></Block></Block>\n"
                        "<DataSet index=\"2\"/>\n</vtkMultiBlockDataSet>\n</VTKFile>\n");
    MultiblockDetails det;
    const Multiblock mb = read_multiblock({P(d, "m.vtm")}, {}, det);
    CHECK(mb.format == "vtm");
    REQUIRE(mb.blocks.size() == 2);
    CHECK(mb.blocks[0].name == "rect");
    CHECK(mb.blocks[1].name == "i.vti");
    CHECK(mb.blocks[0].dims == Dims{3, 2, 4});
    CHECK(mb.blocks[1].dims == Dims{3, 2, 2});
    CHECK(mb.notes.size() == 1);  // the DataSet without a file
    for (const auto& b : mb.blocks)
        for (std::size_t n = 0; n < b.node.size(); ++n)
            CHECK(b.value[n] == Approx(lin(b.node[n].x, b.node[n].y, b.node[n].z)).margin(1e-12));
    CHECK(mb.blocks[0].node[mb.blocks[0].index(2, 1, 3)].x == 3);
    CHECK(mb.blocks[0].node[mb.blocks[0].index(2, 1, 3)].z == 5);
    CHECK(mb.blocks[1].node[0].x == 10.5);  // Origin + Extent lo * Spacing
    CHECK(mb.blocks[1].node[0].y == 0.5);
    REQUIRE(det.arrays.size() == 1);
    CHECK(det.arrays[0].name == "f");
}

TEST_CASE("AMR: .vthb 1.1 and the vtkHierarchicalBoxDataSet .vtm give the same cell-centred blocks", "[multiblock][amr]") {
    TempDir d("mb-amr");
    write_amr_pieces(d);
    spit(P(d, "h.vthb"), vthb_text(amr_boxes()));
    spit(P(d, "h.vtm"), amr_vtm_text(amr_boxes()));
    PointSetOptions o;
    o.value_name = "rho";
    MultiblockDetails det;
    const Multiblock a = read_multiblock({P(d, "h.vthb")}, o, det);
    CHECK(a.format == "vthb");
    check_amr(a);
    REQUIRE(det.levels.size() == 2);
    CHECK(det.levels[0].boxes == 1);
    CHECK(det.levels[1].boxes == 2);
    CHECK(det.levels[1].refinement == 2);
    CHECK(det.levels[1].spacing[2] == 0.5);
    CHECK(det.cell);
    const Multiblock b = read_multiblock({P(d, "h.vtm")}, o, det);
    CHECK(b.format == "vtm-amr");
    check_amr(b);
    REQUIRE(det.origin);
    CHECK((*det.origin)[0] == 0);
    // the default array: the first scalar one (vel has 3 components)
    CHECK(read_multiblock({P(d, "h.vthb")}).value_name == "rho");
    o.value_name = "vel";
    CHECK_THAT(error_of([&] { read_multiblock({P(d, "h.vthb")}, o); }), Catch::Contains("'vel' has 3 components"));
}

TEST_CASE("AMR and .vtm: each defect class is refused with one line naming the collection and the piece", "[multiblock][amr]") {
    TempDir d("mb-amr-bad");
    write_amr_pieces(d);
    PointSetOptions o;
    o.value_name = "rho";
    auto fails = [&](const std::string& name, const std::string& text) {
        spit(P(d, name), text);
        const std::string m = error_of([&] { read_multiblock({P(d, name)}, o); });
        CHECK(m.find('\n') == std::string::npos);
        CHECK(m.find('\x1b') == std::string::npos);
        return m;
    };
    // a missing piece
    auto boxes = amr_boxes();
    boxes[2].file = "gone.vti";
    std::string m = fails("missing.vthb", vthb_text(boxes));
    CHECK_THAT(m, Catch::Contains("missing.vthb: piece 'gone.vti' (level 1 box 1)"));
    m = fails("missing.vtm", "<VTKFile type=\"vtkMultiBlockDataSet\"><vtkMultiBlockDataSet><DataSet index=\"0\" file=\"gone.vts\"/>"
                             "</vtkMultiBlockDataSet></VTKFile>");
    CHECK_THAT(m, Catch::Contains("missing.vtm: piece 'gone.vts'"));
    CHECK_THAT(m, Catch::Contains("gone.vts"));
    // a piece whose extent contradicts its amr_box
    boxes = amr_boxes();
    boxes[1].box = {2, 6, 2, 5, 2, 5};
    m = fails("extent.vthb", vthb_text(boxes));
    CHECK_THAT(m, Catch::Contains("extent.vthb: piece 'p1.vti' (level 1 box 0): its extent has 4 cells along x, its amr_box"));
    // a piece listed twice
    boxes = amr_boxes();
    boxes[2].file = "./p1.vti";
    boxes[2].box = boxes[1].box;
    m = fails("twice.vthb", vthb_text(boxes));
    CHECK_THAT(m, Catch::Contains("twice.vthb: piece './p1.vti' (level 1 box 1): the piece is listed twice"));
    // a piece at another place than its amr_box says (same size)
    boxes = amr_boxes();
    boxes[1].box = {3, 6, 2, 5, 2, 5};
    m = fails("shifted.vthb", vthb_text(boxes));
    CHECK_THAT(m, Catch::Contains("shifted.vthb: piece 'p1.vti' (level 1 box 0): its origin puts amr_box index 3"));
    // level spacing contradicted by the piece (0.1: declared refinement ratio vs the pieces' spacings)
    m = fails("ratio.vtm", amr_vtm_text(amr_boxes(), 4));
    CHECK_THAT(m, Catch::Contains("ratio.vtm: RefinementRatio of level 0 is 4 but the pieces' spacings give 2"));
    std::string t = vthb_text(amr_boxes());
    t.replace(t.find("0.5 0.5 0.5"), 11, "0.25 0.5 0.5");
    m = fails("spacing.vthb", t);
    CHECK_THAT(m, Catch::Contains("spacing.vthb: piece 'p1.vti' (level 1 box 0): Spacing 0.5"));
    // mixed cell/point centring of the chosen array
    TempDir d2("mb-amr-mixed");
    write_amr_pieces(d2, true);
    spit(P(d2, "mixed.vthb"), vthb_text(amr_boxes()));
    CHECK_THAT(error_of([&] { read_multiblock({P(d2, "mixed.vthb")}, o); }),
               Catch::Contains("mixed.vthb: mixed centring: array 'rho' is cell data in piece 'p0.vti' but point data in piece 'p2.vti'"));
    // a truncated piece
    std::string piece = slurp(P(d, "p2.vti"));
    spit(P(d, "p2.vti"), piece.substr(0, piece.size() / 2));
    m = fails("trunc.vthb", vthb_text(amr_boxes()));
    CHECK_THAT(m, Catch::Contains("trunc.vthb: piece 'p2.vti' (level 1 box 1)"));
    CHECK_THAT(m, Catch::Contains("p2.vti: "));
    spit(P(d, "p2.vti"), piece);
    // bytes quoted from the file are escaped
    m = fails("esc.vthb", "<VTKFile type=\"vtkOverlappingAMR\" version=\"1.1\"><vtkOverlappingAMR origin=\"0 0 0\">"
                          "<Block level=\"0\" spacing=\"1 1 1\"><DataSet index=\"0\" amr_box=\"0 3\x1b[31m 0 3 0 3\" file=\"p0.vti\"/>"
                          "</Block></vtkOverlappingAMR></VTKFile>");
    CHECK_THAT(m, Catch::Contains("\\x1b[31m"));
    // a piece that is itself a collection; an unknown collection type; huge extents
    m = fails("nested.vtm", "<VTKFile type=\"vtkMultiBlockDataSet\"><vtkMultiBlockDataSet><DataSet file=\"missing.vtm\"/>"
                            "</vtkMultiBlockDataSet></VTKFile>");
    CHECK_THAT(m, Catch::Contains("unsupported piece type '.vtm'"));
    m = fails("poly.vtm", "<VTKFile type=\"PolyData\"><PolyData/></VTKFile>");
    CHECK_THAT(m, Catch::Contains("poly.vtm: VTK XML type 'PolyData' is not a collection"));
    write_vti(P(d, "huge.vti"), {0, 4000000000, 0, 4000000000, 0, 4000000000}, {0, 0, 0}, {1, 1, 1}, {Arr{"rho", {1, 2}}});
    CHECK_THAT(error_of([&] { read_multiblock({P(d, "huge.vti")}); }), Catch::Contains("huge.vti: piece 0: Extent"));
    write_vti(P(d, "big.vti"), {0, 400, 0, 400, 0, 400}, {0, 0, 0}, {1, 1, 1}, {Arr{"rho", {1, 2}}});
    CHECK_THAT(error_of([&] { read_multiblock({P(d, "big.vti")}); }), Catch::Contains("more than the"));
}

// ------------------------------------------------------------------------------------- real data

TEST_CASE("real PLOT3D and VTS multiblock data loads as blocks with the structure of SOURCES.md", "[multiblock][real]") {
    if (!meshless::test::have_shared_data()) {
        WARN("shared data absent: real multiblock tests skipped");
        return;
    }
    {
        const Multiblock c = read_multiblock({R("plot3d/combxyz.bin")});
        REQUIRE(c.blocks.size() == 1);
        CHECK(c.blocks[0].dims == Dims{57, 33, 25});
        CHECK(c.blanked == 0);
        CHECK(c.blocks[0].valid.empty());
        const auto [lo, hi] = std::minmax_element(c.blocks[0].value.begin(), c.blocks[0].value.end());
        CHECK(*lo == Approx(0.1978).margin(5e-5));
        CHECK(*hi == Approx(0.7104).margin(5e-5));
        const Multiblock m = read_multiblock({R("plot3d/test.p3d")});
        CHECK(m.blocks.at(0).value == c.blocks[0].value);
    }
    {
        PointSetOptions o;
        o.q_component = 4;
        const Multiblock p = read_multiblock({R("plot3d/postxyz.bin")}, o);
        REQUIRE(p.blocks.size() == 1);
        CHECK(p.blocks[0].dims == Dims{38, 76, 38});
        const PointSet ps = read_point_set(R("plot3d/postxyz.bin"), o);
        CHECK(p.blanked == ps.dropped_blanked);
        CHECK(p.blanked == 0);  // its IBLANK is 1 or -1 (4,332 fringe nodes), never 0: every node is data
        std::uint64_t valid = 0;
        for (std::int64_t n = 0; n < p.blocks[0].node_count(); ++n) valid += p.blocks[0].is_valid(n);
        CHECK(valid == ps.size());
    }
    {
        PointSetOptions o;
        o.allow_trailing = true;
        CHECK(read_multiblock({R("plot3d/bluntfinxyz.bin")}, o).blocks.at(0).dims == Dims{40, 32, 32});
    }
    for (const char* f : {"plot3d/multi-bin.xyz", "plot3d/multi-bin-C.xyz", "plot3d/multi-ascii.xyz", "plot3d/multi.p3d"}) {
        INFO(f);
        const Multiblock m = read_multiblock({R(f)});
        REQUIRE(m.blocks.size() == 2);
        CHECK(m.blocks[0].dims == Dims{8, 12, 12});
        CHECK(m.blocks[1].dims == Dims{8, 12, 12});
        CHECK(m.blocks[1].name == "grid 2");
    }
    {
        PointSetOptions o;
        o.function_file = R("plot3d/multi-bin.f");
        CHECK(read_multiblock({R("plot3d/multi-bin.xyz")}, o).value_name == "function 0");
        const Multiblock w = read_multiblock({R("plot3d/mbwavelet_ascii.xyz")});
        REQUIRE(w.blocks.size() == 3);
        for (const auto& b : w.blocks) CHECK(b.dims == Dims{4, 11, 11});
    }
    {
        const Multiblock m = read_multiblock({R("plot3d/multicomb_0.vts"), R("plot3d/multicomb_1.vts"), R("plot3d/multicomb_2.vts")});
        REQUIRE(m.blocks.size() == 3);
        CHECK(m.blocks[0].dims == Dims{6, 12, 9});
        CHECK(m.blocks[1].dims == Dims{8, 12, 9});
        CHECK(m.blocks[2].dims == Dims{9, 12, 9});
        CHECK(m.value_name == "Density");
        CHECK(m.blocks[1].name == "multicomb_1.vts");
        // the same nodes and values as the point-set reader
        const PointSet ps = read_point_set({R("plot3d/multicomb_0.vts"), R("plot3d/multicomb_1.vts"), R("plot3d/multicomb_2.vts")});
        const PointSet again = to_point_set(m);
        REQUIRE(again.size() == ps.size());
        for (std::size_t i = 0; i < ps.size(); ++i) {
            REQUIRE(again.pos[i].x == ps.pos[i].x);
            REQUIRE(again.value[i] == ps.value[i]);
        }
        PointSetOptions o;
        o.value_name = "Momentum";
        CHECK_THAT(error_of([&] { read_multiblock({R("plot3d/multicomb_0.vts")}, o); }),
                   Catch::Contains("'Momentum' has 3 components; a block input needs a scalar (scalar arrays: 'Density' (point)"));
    }
}

TEST_CASE("real AMR hierarchies load with the levels, boxes and ranges of SOURCES.md", "[multiblock][amr][real]") {
    if (!meshless::test::have_shared_data()) {
        WARN("shared data absent: real AMR tests skipped");
        return;
    }
    auto count_nodes = [](const Multiblock& m) {
        std::uint64_t n = 0;
        for (const auto& b : m.blocks) n += b.node.size();
        return n;
    };
    auto range = [](const Multiblock& m) {
        double lo = 1e300, hi = -1e300;
        for (const auto& b : m.blocks)
            for (double v : b.value) lo = std::min(lo, v), hi = std::max(hi, v);
        return std::array<double, 2>{lo, hi};
    };
    {
        // chombo3d: vtkHierarchicalBoxDataSet 0.1, 3 levels (1 + 1 + 14 boxes), refinement 2, cell data phi.
        // Cell count and range computed with VTK 9.1's vtkXMLImageDataReader over the 16 pieces.
        MultiblockDetails det;
        const Multiblock c = read_multiblock({R("amr/chombo3d/chombo3d.vtm")}, {}, det);
        CHECK(c.format == "vtm-amr");
        CHECK(c.value_name == "phi");
        REQUIRE(c.blocks.size() == 16);
        REQUIRE(det.levels.size() == 3);
        CHECK(det.levels[0].boxes == 1);
        CHECK(det.levels[1].boxes == 1);
        CHECK(det.levels[2].boxes == 14);
        CHECK(det.levels[1].refinement == 2);
        CHECK(det.levels[2].refinement == 2);
        CHECK(det.levels[2].spacing[0] == Approx(0.25));
        CHECK(det.levels[0].spacing[0] == Approx(1.0));
        CHECK(count_nodes(c) == 10176);
        for (const auto& b : c.blocks) CHECK(b.cell_centred);
        const StructuredBlock& b2 = c.blocks[2];  // chombo3d_2.vti: 13x17x17 points, spacing 0.25, origin (0,2,2)
        CHECK(b2.level == 2);
        CHECK(b2.dims == Dims{12, 16, 16});
        CHECK(b2.node[0].x == Approx(0.125));
        CHECK(b2.node[0].y == Approx(2.125));
        const auto [lo2, hi2] = std::minmax_element(b2.value.begin(), b2.value.end());
        CHECK(*lo2 == Approx(-0.0367).margin(5e-5));
        CHECK(*hi2 == Approx(-0.0013).margin(5e-5));
        const auto r = range(c);
        CHECK(r[0] == Approx(-0.0391938073).epsilon(1e-8));
        CHECK(r[1] == Approx(-3.70335606e-05).epsilon(1e-8));
    }
    {
        // VTK's AMR test set: vtkOverlappingAMR 1.1, 4 levels of 1, 8, 40, 32 boxes, cell data.
        PointSetOptions o;
        o.value_name = "Fractal Volume Fraction";
        MultiblockDetails det;
        const Multiblock h = read_multiblock({R("amr/HierarchicalBoxDataset.v1.1.vthb")}, o, det);
        CHECK(h.format == "vthb");
        REQUIRE(h.blocks.size() == 81);
        REQUIRE(det.levels.size() == 4);
        CHECK(det.levels[0].boxes == 1);
        CHECK(det.levels[1].boxes == 8);
        CHECK(det.levels[2].boxes == 40);
        CHECK(det.levels[3].boxes == 32);
        for (int l = 1; l < 4; ++l) CHECK(det.levels[l].refinement == 2);
        CHECK(det.levels[0].spacing[0] == Approx(0.833333));
        CHECK(det.levels[0].spacing[2] == Approx(0.666667));
        REQUIRE(det.origin);
        CHECK((*det.origin)[0] == Approx(-1.75));
        CHECK((*det.origin)[1] == Approx(-1.25));
        CHECK(count_nodes(h) == 2556);
        const StructuredBlock& b5 = h.blocks[5];  // piece _5: 4x4x4 points -> 3x3x3 cells
        CHECK(b5.dims == Dims{3, 3, 3});
        CHECK(b5.level == 1);
        const auto r = range(h);
        CHECK(r[0] == Approx(0.0533417087).epsilon(1e-8));
        CHECK(r[1] == Approx(5.26315789).epsilon(1e-8));
        bool cell = false, vector = false;
        for (const auto& a : det.arrays) {
            if (a.name == "Fractal Volume Fraction") cell = a.cell;
            if (a.name == "VectorXYZ") vector = a.components == 3;
        }
        CHECK(cell);
        CHECK(vector);
        // default: the first scalar array (TestX); the vector array is refused
        const Multiblock t = read_multiblock({R("amr/HierarchicalBoxDataset.v1.1.vthb")});
        CHECK(t.value_name == "TestX");
        CHECK(range(t)[0] == Approx(-2.89583334).epsilon(1e-7));
        o.value_name = "VectorXYZ";
        CHECK_THAT(error_of([&] { read_multiblock({R("amr/HierarchicalBoxDataset.v1.1.vthb")}, o); }),
                   Catch::Contains("'VectorXYZ' has 3 components"));
    }
}

TEST_CASE("a regular volume is one block of its voxels", "[multiblock]") {
    TempDir d("mb-vol");
    std::string b;
    for (int k = 0; k < 2; ++k)
        for (int j = 0; j < 3; ++j)
            for (int i = 0; i < 4; ++i) b.push_back(static_cast<char>(i + 4 * j + 12 * k));
    spit(P(d, "v_4x3x2_uint8.raw"), b);
    CHECK_FALSE(looks_like_multiblock(P(d, "v_4x3x2_uint8.raw")));
    const Multiblock mb = read_multiblock({P(d, "v_4x3x2_uint8.raw")});
    CHECK(mb.format == "volume");
    REQUIRE(mb.blocks.size() == 1);
    CHECK(mb.blocks[0].dims == Dims{4, 3, 2});
    for (std::size_t n = 0; n < 24; ++n)
        CHECK(mb.blocks[0].value[n] == mb.blocks[0].node[n].x + 4 * mb.blocks[0].node[n].y + 12 * mb.blocks[0].node[n].z);
}

TEST_CASE("AMR with point data: each box's points as they are, checked against its amr_box", "[multiblock][amr]") {
    TempDir d("mb-amr-points");
    for (const auto& b : amr_boxes()) {
        const double h = b.level == 0 ? 1.0 : 0.5;
        const std::array<std::int64_t, 3> cells{b.box[1] - b.box[0] + 1, b.box[3] - b.box[2] + 1, b.box[5] - b.box[4] + 1};
        Arr f{"p", {}};
        for (int k = 0; k <= cells[2]; ++k)
            for (int j = 0; j <= cells[1]; ++j)
                for (int i = 0; i <= cells[0]; ++i) f.v.push_back(lin((b.box[0] + i) * h, (b.box[2] + j) * h, (b.box[4] + k) * h));
        // the pieces' extents start where their boxes do (as VTK writes global extents)
        write_vti(P(d, b.file), {b.box[0], b.box[1] + 1, b.box[2], b.box[3] + 1, b.box[4], b.box[5] + 1}, {0, 0, 0}, {h, h, h}, {f});
    }
    spit(P(d, "h.vthb"), vthb_text(amr_boxes()));
    MultiblockDetails det;
    const Multiblock mb = read_multiblock({P(d, "h.vthb")}, {}, det);
    REQUIRE(mb.blocks.size() == 3);
    CHECK_FALSE(det.cell);
    const auto boxes = amr_boxes();
    for (std::size_t b = 0; b < 3; ++b) {
        const StructuredBlock& blk = mb.blocks[b];
        CHECK_FALSE(blk.cell_centred);
        CHECK(blk.level == boxes[b].level);
        CHECK(blk.dims == Dims{boxes[b].box[1] - boxes[b].box[0] + 2, boxes[b].box[3] - boxes[b].box[2] + 2,
                               boxes[b].box[5] - boxes[b].box[4] + 2});
        const double h = boxes[b].level == 0 ? 1.0 : 0.5;
        CHECK(blk.node[0].x == boxes[b].box[0] * h);
        CHECK(blk.node[0].z == boxes[b].box[4] * h);
        for (std::size_t n = 0; n < blk.node.size(); ++n)
            REQUIRE(blk.value[n] == Approx(lin(blk.node[n].x, blk.node[n].y, blk.node[n].z)).margin(1e-12));
    }
}
