// The VTK XML writers of `meshless split` (formats/vts_writer, vtm_writer, vthb_writer): round
// trips through the project's own readers (nodes and values equal), the structure of the .vtm and
// .vthb indices, atomicity on failure, and — when python3-vtk9 is installed — VTK's own readers
// (vtkXMLMultiBlockDataReader, vtkXMLUniformGridAMRReader) reading what was written.
#include <catch2/catch.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "formats/points_vts.hpp"
#include "formats/vthb_writer.hpp"
#include "formats/vtk_xml.hpp"
#include "formats/vtm_writer.hpp"
#include "formats/vts_writer.hpp"
#include "kernels/analytic_volumes.hpp"
#include "kernels/errors.hpp"
#include "kernels/multiblock_split.hpp"
#include "test_paths.hpp"

using namespace meshless;
using meshless::test::TempDir;
namespace fs = std::filesystem;

namespace {

std::string slurp(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

/// An 8-bit volume (values exact in the Float32 the .vts stores) of the torus field, 17 x 13 x 11.
Volume small_volume() {
    GridSpec g;
    g.dims = {17, 13, 11};
    g.origin = {-1, -0.75, -0.6};
    g.spacing = {0.125, 0.125, 0.12};
    Volume v(g, SampleType::u8);
    for (std::int64_t k = 0; k < 11; ++k)
        for (std::int64_t j = 0; j < 13; ++j)
            for (std::int64_t i = 0; i < 17; ++i) {
                const Vec3 p{-1 + 0.125 * i, -0.75 + 0.125 * j, -0.6 + 0.12 * k};
                v.bytes.data()[g.index(i, j, k)] =
                    static_cast<std::byte>(static_cast<int>(std::lround(200 * analytic_value(AnalyticField::torus, p))) & 255);
            }
    return v;
}

bool no_temporaries(const fs::path& dir) {
    for (const auto& e : fs::recursive_directory_iterator(dir))
        if (e.path().filename().string().find(".tmp-") != std::string::npos) return false;
    return true;
}

bool have_vtk() { return std::system("/usr/bin/python3 -c 'import vtk' >/dev/null 2>&1") == 0; }

std::string run_python(const std::string& script, const TempDir& dir) {
    const fs::path py = dir / "check.py", out = dir / "py.txt";
    std::ofstream(py) << script;
    const int rc = std::system(("/usr/bin/python3 '" + py.string() + "' >'" + out.string() + "' 2>&1").c_str());
    const std::string text = slurp(out);
    INFO(text);
    REQUIRE(rc == 0);
    return text;
}

}  // namespace

TEST_CASE("vtm writer: every layout's pieces read back with the block's nodes and values", "[vtm_writer]") {
    TempDir dir("vtm-writer");
    const Volume v = small_volume();
    for (SplitLayout layout : {SplitLayout::overlapping, SplitLayout::semi_conforming, SplitLayout::non_conforming,
                               SplitLayout::rotated}) {
        SplitParams p;
        p.blocks = 3;
        const Multiblock mb = split_volume(v.view(), layout, p, "density");
        const std::string name = std::string(to_string(layout));
        const fs::path vtm = dir / (name + ".vtm");
        const auto pieces = write_vtm(vtm.string(), mb);
        REQUIRE(pieces.size() == mb.blocks.size());
        const std::string index = slurp(vtm);
        CHECK(index.find("type=\"vtkMultiBlockDataSet\"") != std::string::npos);
        for (std::size_t b = 0; b < mb.blocks.size(); ++b) {
            const std::string rel = name + "/" + name + "_" + std::to_string(b) + ".vts";
            CHECK(index.find("file=\"" + rel + "\"") != std::string::npos);
            CHECK(fs::path(pieces[b]) == vtm.parent_path() / rel);
            const PointSet ps = read_points_vts(pieces[b], PointSetOptions{});
            const auto& blk = mb.blocks[b];
            REQUIRE(ps.size() == blk.node.size());
            CHECK(ps.value_name == "density");
            REQUIRE(ps.blocks.size() == 1);
            CHECK(ps.blocks[0].dims == blk.dims);
            for (std::size_t n = 0; n < ps.size(); ++n) {
                REQUIRE(ps.pos[n].x == blk.node[n].x);
                REQUIRE(ps.pos[n].y == blk.node[n].y);
                REQUIRE(ps.pos[n].z == blk.node[n].z);
                REQUIRE(ps.value[n] == Approx(blk.value[n]).epsilon(1e-6));  // float32 of the value
                if (layout == SplitLayout::overlapping || layout == SplitLayout::semi_conforming)
                    REQUIRE(ps.value[n] == blk.value[n]);  // the volume's own 8-bit samples: exact
            }
        }
    }
    CHECK(no_temporaries(dir.path));
}

TEST_CASE("vthb writer: the index names levels, spacings and boxes, the pieces hold the cell values", "[vtm_writer]") {
    TempDir dir("vthb-writer");
    const Volume v = small_volume();
    AmrParams ap;
    ap.iso = 50;
    ap.tile = 2;
    const AmrHierarchy h = split_amr(v.view(), ap, "phi");
    REQUIRE(h.boxes.size() > 3);
    const fs::path out = dir / "h.vthb";
    const auto pieces = write_vthb(out.string(), h);
    REQUIRE(pieces.size() == h.boxes.size());
    const std::string doc = slurp(out);
    const std::string path = out.string();
    CHECK(doc.find("type=\"vtkOverlappingAMR\" version=\"1.1\"") != std::string::npos);
    const VtkXmlDocument X(doc, path);
    const std::vector<VtkXmlElement> blocks = X.root().child("vtkOverlappingAMR").children("Block");
    REQUIRE(blocks.size() >= 3);
    std::size_t piece = 0;
    for (int level = 0; level < 3; ++level) {
        const VtkXmlElement blk = blocks[static_cast<std::size_t>(level)];
        CHECK(blk.attr("level") == std::to_string(level));
        const auto s = h.spacing(level);
        double sx, sy, sz;
        REQUIRE(std::sscanf(blk.attr("spacing").c_str(), "%lf %lf %lf", &sx, &sy, &sz) == 3);
        CHECK(sx == s[0]);
        CHECK(sy == s[1]);
        CHECK(sz == s[2]);
        const std::vector<VtkXmlElement> sets = blk.children("DataSet");
        std::size_t next = 0;
        for (const AmrBox& b : h.boxes) {
            if (b.level != level) continue;
            REQUIRE(next < sets.size());
            const VtkXmlElement ds = sets[next++];
            long long box[6];
            REQUIRE(std::sscanf(ds.attr("amr_box").c_str(), "%lld %lld %lld %lld %lld %lld", &box[0], &box[1], &box[2],
                                &box[3], &box[4], &box[5]) == 6);
            CHECK(box[0] == b.lo[0]);
            CHECK(box[1] == b.hi[0]);
            CHECK(box[4] == b.lo[2]);
            CHECK(box[5] == b.hi[2]);
            const fs::path vti = out.parent_path() / ds.attr("file");
            CHECK(vti == fs::path(pieces[piece++]));
            // the piece: extent lo..hi+1, the cell array equal to the box's values
            const std::string pd = slurp(vti);
            const VtkXmlDocument P(pd, vti.string());
            CHECK(P.file().type == "ImageData");
            const VtkXmlElement pc = P.root().child("ImageData").child("Piece");
            CHECK(pc.attr("Extent") == std::to_string(b.lo[0]) + " " + std::to_string(b.hi[0] + 1) + " " +
                                           std::to_string(b.lo[1]) + " " + std::to_string(b.hi[1] + 1) + " " +
                                           std::to_string(b.lo[2]) + " " + std::to_string(b.hi[2] + 1));
            const VtkXmlElement cd = pc.child("CellData");
            CHECK(cd.attr("Scalars") == "phi");
            const VtkXmlElement arr = cd.child("DataArray");
            const auto values = vtk_xml_read_array(P, arr, b.value.size(), vti.string());
            REQUIRE(values == b.value);
        }
        CHECK(next == sets.size());
    }
    CHECK(no_temporaries(dir.path));
}

TEST_CASE("VTK reads the written .vtm and .vthb (python3-vtk9)", "[vtm_writer][vtk]") {
    if (!have_vtk()) {
        WARN("python3-vtk9 not installed: VTK read-back skipped");
        return;
    }
    TempDir dir("vtk-read");
    const Volume v = small_volume();
    std::vector<Multiblock> mbs;
    std::string vtms;
    for (SplitLayout layout : {SplitLayout::overlapping, SplitLayout::semi_conforming, SplitLayout::non_conforming,
                               SplitLayout::rotated}) {
        mbs.push_back(split_volume(v.view(), layout, {}, "density"));
        const std::string path = (dir / (std::string(to_string(layout)) + ".vtm")).string();
        write_vtm(path, mbs.back());
        vtms += (vtms.empty() ? "'" : ", '") + path + "'";
    }
    AmrParams ap;
    ap.iso = 50;
    ap.tile = 2;
    const AmrHierarchy h = split_amr(v.view(), ap, "phi");
    write_vthb((dir / "h.vthb").string(), h);
    const std::string text = run_python(
        "import vtk\n"
        "for f in [" + vtms + "]:\n"
        "  r = vtk.vtkXMLMultiBlockDataReader(); r.SetFileName(f); r.Update()\n"
        "  o = r.GetOutput()\n"
        "  for i in range(o.GetNumberOfBlocks()):\n"
        "    b = o.GetBlock(i); a = b.GetPointData().GetScalars(); p = b.GetPoint(b.GetNumberOfPoints() - 1)\n"
        "    print('block', b.GetNumberOfPoints(), *b.GetDimensions(), a.GetName(), '%.6f' % sum(a.GetValue(k) for k in range(a.GetNumberOfTuples())), '%.9g %.9g %.9g' % p)\n"
        "r = vtk.vtkXMLUniformGridAMRReader(); r.SetFileName('" + (dir / "h.vthb").string() + "')\n"
        "r.SetMaximumLevelsToReadByDefault(0); r.Update(); o = r.GetOutput()\n"
        "print('levels', o.GetNumberOfLevels(), *[o.GetNumberOfDataSets(l) for l in range(o.GetNumberOfLevels())])\n"
        "for l in range(o.GetNumberOfLevels()):\n"
        "    for i in range(o.GetNumberOfDataSets(l)):\n"
        "        d = o.GetDataSet(l, i); a = d.GetCellData().GetArray('phi')\n"
        "        print('box', l, d.GetNumberOfCells(), '%.6f' % sum(a.GetValue(k) for k in range(a.GetNumberOfTuples())), '%.9g %.9g' % d.GetBounds()[0:2])\n",
        dir);
    std::string expect;
    char line[256];
    for (const Multiblock& mb : mbs)
        for (const auto& b : mb.blocks) {
            double s = 0;
            for (double x : b.value) s += static_cast<float>(x);
            const Vec3 p = b.node.back();
            std::snprintf(line, sizeof line, "block %zu %lld %lld %lld density %.6f %.9g %.9g %.9g\n", b.node.size(),
                          static_cast<long long>(b.dims[0]), static_cast<long long>(b.dims[1]),
                          static_cast<long long>(b.dims[2]), s, p.x, p.y, p.z);
            expect += line;
        }
    int count[3] = {0, 0, 0};
    for (const AmrBox& b : h.boxes) ++count[b.level];
    std::snprintf(line, sizeof line, "levels 3 %d %d %d\n", count[0], count[1], count[2]);
    expect += line;
    for (int l = 0; l < 3; ++l)
        for (const AmrBox& b : h.boxes) {
            if (b.level != l) continue;
            double s = 0;
            for (double x : b.value) s += x;
            const double x0 = h.origin[0] + static_cast<double>(b.lo[0]) * h.spacing(l)[0];
            const double x1 = h.origin[0] + static_cast<double>(b.hi[0] + 1) * h.spacing(l)[0];
            std::snprintf(line, sizeof line, "box %d %zu %.6f %.9g %.9g\n", l, b.value.size(), s, x0, x1);
            expect += line;
        }
    CHECK(text == expect);
}

TEST_CASE("multiblock writers: bad paths and bad blocks fail cleanly", "[vtm_writer]") {
    TempDir dir("vtm-bad");
    const Volume v = small_volume();
    const Multiblock mb = split_volume(v.view(), SplitLayout::overlapping);
    CHECK_THROWS_AS(write_vtm((dir / "x.vts").string(), mb), InvalidArgument);
    CHECK_THROWS_AS(write_vtm((dir / "x.vtm").string(), Multiblock{}), InvalidArgument);
    CHECK_THROWS_AS(write_vthb((dir / "x.vtm").string(), split_amr(v.view())), InvalidArgument);
    // the pieces' folder cannot be made: a regular file is in the way
    std::ofstream(dir / "blocked") << "x";
    CHECK_THROWS_AS(write_vtm((dir / "blocked.vtm").string(), mb), IoError);
    CHECK(!fs::exists(dir / "blocked.vtm"));
    // a block whose arrays disagree with its dims: nothing written
    StructuredBlock bad = mb.blocks[0];
    bad.value.pop_back();
    CHECK_THROWS_AS(write_vts((dir / "bad.vts").string(), bad, "v"), InvalidArgument);
    CHECK(!fs::exists(dir / "bad.vts"));
    CHECK(no_temporaries(dir.path));
    // names are escaped in the XML
    CHECK(vtk_xml_escape("a<b>&\"c\x01") == "a&lt;b&gt;&amp;&quot;c?");
}
