// Tests for formats/vtp_writer.hpp. Oracles: round trips through the project's own VTK XML reader
// (formats/vtk_xml.hpp, formats/points_vtp.hpp: every array, bit for bit, compressed and not, with
// blocks smaller than a batch so that arrays span many blocks), the VTK block layout checked by
// hand, peak RSS while streaming 10^6 points (must not grow with the count), and the files an
// interrupted writer leaves (none). VTK's own reader is exercised in tests/cli/test_vtp_cli.cpp.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "../test_paths.hpp"
#include "point_record_samples.hpp"
#include "formats/points_vtp.hpp"
#include "formats/vtk_xml.hpp"
#include "formats/vtp_writer.hpp"
#include "kernels/analytic_volumes.hpp"
#include "kernels/errors.hpp"
#include "kernels/marching_cubes.hpp"

using namespace meshless;
namespace fs = std::filesystem;

namespace {

std::string slurp(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

PointRecord point(std::uint64_t i) { return test::sample_point_record(i); }

/// Every array of a written file, read back with the project's VTK XML reader.
struct Parsed {
    std::unique_ptr<const std::string> bytes;  // the document reads appended arrays from them
    std::unique_ptr<const VtkXmlDocument> x;
    std::string_view doc;
    VtkXmlFile f;
    std::uint64_t points = 0, verts = 0, polys = 0;
    std::vector<double> array(const std::string& name, std::uint64_t count) const {
        for (const VtkXmlElement& t : x->root().descendants("DataArray"))
            if (t.attr("Name") == name) return vtk_xml_read_array(*x, t, count, "t.vtp");
        FAIL("no array " << name);
        return {};
    }
    bool has(const std::string& name) const { return doc.find("Name=\"" + name + "\"") != std::string::npos; }
};

Parsed parse(const fs::path& p) {
    Parsed r;
    r.bytes = std::make_unique<const std::string>(slurp(p));
    r.doc = *r.bytes;
    r.x = std::make_unique<const VtkXmlDocument>(r.doc, p.string());
    r.f = r.x->file();
    REQUIRE(r.f.type == "PolyData");
    REQUIRE(r.f.header64);
    const VtkXmlElement piece = r.x->root().child("PolyData").child("Piece");
    REQUIRE(piece.found());
    r.points = std::stoull(piece.attr("NumberOfPoints"));
    r.verts = std::stoull(piece.attr("NumberOfVerts"));
    r.polys = std::stoull(piece.attr("NumberOfPolys"));
    return r;
}

long peak_rss_kib() {
    std::ifstream in("/proc/self/status");
    std::string line;
    while (std::getline(in, line))
        if (line.rfind("VmHWM:", 0) == 0) return std::stol(line.substr(6));
    return -1;
}

}  // namespace

TEST_CASE("vtp points: every array round trips, compressed or not, across many blocks", "[vtp]") {
    meshless::test::TempDir d("vtp-points");
    for (const bool zlib : {true, false}) {
        for (const bool blocks : {false, true}) {
            INFO("zlib " << zlib << " blocks " << blocks);
            VtpOptions o;
            o.compression = zlib ? VtpCompression::zlib : VtpCompression::none;
            o.block_size = 1000;  // not a multiple of a record: arrays straddle block ends
            const fs::path path = d / "p.vtp";
            const std::uint64_t n = 20011;
            {
                VtpPointWriter w(path.string(), {"first comment", "has -- dashes, <tags> & a \xff byte-"}, o);
                std::uint64_t i = 0;
                for (std::uint64_t batch : {0, 1, 4096, 0, 9000, 6914}) {
                    std::vector<PointRecord> pts;
                    std::vector<std::uint32_t> ids;
                    for (std::uint64_t k = 0; k < batch; ++k, ++i) {
                        pts.push_back(point(i));
                        ids.push_back(static_cast<std::uint32_t>(i % 13));
                    }
                    if (blocks) w.append(pts, ids);
                    else w.append(pts);
                }
                REQUIRE(i == n);
                CHECK(w.count() == n);
                w.commit();
            }
            const Parsed P = parse(path);
            CHECK(P.f.compressed == zlib);
            CHECK(P.points == n);
            CHECK(P.verts == n);
            CHECK(P.polys == 0);
            const auto xyz = P.array("Points", 3 * n), nrm = P.array("Normals", 3 * n), rad = P.array("radius", n),
                       val = P.array("value", n), conn = P.array("connectivity", n), offs = P.array("offsets", n);
            for (std::uint64_t i = 0; i < n; ++i) {
                const PointRecord e = point(i);
                for (int c = 0; c < 3; ++c) {
                    REQUIRE(xyz[3 * i + c] == static_cast<double>(e.pos[c]));
                    REQUIRE(nrm[3 * i + c] == static_cast<double>(e.normal[c]));
                }
                REQUIRE(rad[i] == static_cast<double>(e.radius));
                REQUIRE(val[i] == static_cast<double>(e.value));
                REQUIRE(conn[i] == static_cast<double>(i));
                REQUIRE(offs[i] == static_cast<double>(i + 1));
            }
            CHECK(P.has("block") == blocks);
            if (blocks) {
                const auto b = P.array("block", n);
                for (std::uint64_t i = 0; i < n; ++i) REQUIRE(b[i] == static_cast<double>(i % 13));
            }
            // the attributes ParaView picks up, the comment made legal XML
            CHECK(P.doc.find("<PointData Normals=\"Normals\" Scalars=\"value\">") != std::string::npos);
            const std::string head(P.doc.substr(0, P.doc.find("<VTKFile")));
            CHECK(head.find("has -\\x2d dashes, <tags> & a \\xff byte- ") != std::string::npos);
            for (std::size_t c = head.find("<!--"); c != std::string::npos; c = head.find("<!--", c + 4)) {
                const std::size_t e = head.find("-->", c + 4);
                REQUIRE(e != std::string::npos);
                CHECK(head.substr(c + 4, e - c - 4).find("--") == std::string::npos);
            }
            // the project's point reader: positions and the Scalars array
            const PointSet ps = read_points_vtp(path.string(), {});
            REQUIRE(ps.size() == n);
            CHECK(ps.value_name == "value");
            for (std::uint64_t i = 0; i < n; i += 97) {
                CHECK(ps.pos[i].x == static_cast<double>(point(i).pos[0]));
                CHECK(ps.value[i] == static_cast<double>(point(i).value));
            }
        }
    }
}

TEST_CASE("vtp points: unoriented samples leave out Normals and radius", "[vtp]") {
    meshless::test::TempDir d("vtp-unoriented");
    VtpOptions o;
    o.oriented = false;
    o.block_size = 1000;
    const fs::path path = d / "s.vtp";
    const std::uint64_t n = 3001;
    {
        VtpPointWriter w(path.string(), {}, o);
        std::vector<PointRecord> pts;
        for (std::uint64_t i = 0; i < n; ++i) pts.push_back(point(i));
        w.append(std::span(pts).first(1000));
        w.append(std::span(pts).subspan(1000));
        w.commit();
    }
    const Parsed P = parse(path);
    CHECK(P.points == n);
    CHECK(P.verts == n);
    CHECK_FALSE(P.has("Normals"));
    CHECK_FALSE(P.has("radius"));
    CHECK(P.doc.find("<PointData Scalars=\"value\">") != std::string::npos);
    const auto xyz = P.array("Points", 3 * n), val = P.array("value", n), conn = P.array("connectivity", n);
    for (std::uint64_t i = 0; i < n; ++i) {
        for (int c = 0; c < 3; ++c) REQUIRE(xyz[3 * i + c] == static_cast<double>(point(i).pos[c]));
        REQUIRE(val[i] == static_cast<double>(point(i).value));
        REQUIRE(conn[i] == static_cast<double>(i));
    }
}

TEST_CASE("vtp points: the value array named as asked, escaped, and kept apart from the other arrays' names", "[vtp]") {
    meshless::test::TempDir d("vtp-value-name");
    const std::vector<PointRecord> pts{point(0), point(1), point(2)};
    const auto written = [&](const std::string& name) {
        VtpOptions o;
        o.value_name = name;
        const fs::path path = d / "n.vtp";
        VtpPointWriter w(path.string(), {}, o);
        w.append(pts);
        w.commit();
        return slurp(path);
    };
    const std::string t = written("temperature");
    CHECK(t.find("<PointData Normals=\"Normals\" Scalars=\"temperature\">") != std::string::npos);
    CHECK(t.find("Name=\"temperature\"") != std::string::npos);
    CHECK(written("a<b&\"c").find("Name=\"a&lt;b&amp;&quot;c\"") != std::string::npos);
    const std::string r = written("radius");  // (the splat radius keeps its name)
    CHECK(r.find("Name=\"radius_value\"") != std::string::npos);
    CHECK(r.find("Name=\"radius\"") != std::string::npos);
    CHECK(written("").find("Scalars=\"value\"") != std::string::npos);
    // read back: the active scalars are the values, whatever their name
    (void)written("temperature");
    const PointSet back = read_points_vtk_xml((d / "n.vtp").string(), "PolyData", {});
    REQUIRE(back.size() == 3);
    CHECK(back.value[1] == static_cast<double>(point(1).value));
}

TEST_CASE("vtp points: the compressed block layout is VTK's", "[vtp]") {
    meshless::test::TempDir d("vtp-layout");
    VtpOptions o;
    o.block_size = 4096;
    const fs::path path = d / "p.vtp";
    {
        VtpPointWriter w(path.string(), {}, o);
        std::vector<PointRecord> pts;
        for (std::uint64_t i = 0; i < 1000; ++i) pts.push_back(point(i));
        w.append(pts);
        w.commit();
    }
    const std::string doc = slurp(path);
    const std::size_t at = doc.find("offset=\"", doc.find("Name=\"radius\"")) + 8;
    const std::size_t off = std::stoull(doc.substr(at));
    const std::size_t base = doc.find('_', doc.find("<AppendedData")) + 1;
    std::uint64_t h[3];
    std::memcpy(h, doc.data() + base + off, sizeof h);
    // 4000 bytes of radius: one partial block of 4000 (last_block_size 4000)
    CHECK(h[0] == 1);
    CHECK(h[1] == 4096);
    CHECK(h[2] == 4000);
    // Points: 12000 bytes = 2 full blocks + 3808 bytes
    const std::size_t pat = doc.find("offset=\"", doc.find("Name=\"Points\"")) + 8;
    std::memcpy(h, doc.data() + base + std::stoull(doc.substr(pat)), sizeof h);
    CHECK(h[0] == 3);
    CHECK(h[1] == 4096);
    CHECK(h[2] == 12000 - 2 * 4096);
    CHECK(doc.substr(doc.size() - 30) == "\n  </AppendedData>\n</VTKFile>\n");
}

TEST_CASE("vtp points: an empty point set is a valid file", "[vtp]") {
    meshless::test::TempDir d("vtp-empty");
    for (const bool zlib : {true, false}) {
        const fs::path path = d / "e.vtp";
        VtpOptions o;
        o.compression = zlib ? VtpCompression::zlib : VtpCompression::none;
        {
            VtpPointWriter w(path.string(), {}, o);
            w.append({});
            w.commit();
        }
        const Parsed P = parse(path);
        CHECK(P.points == 0);
        CHECK(P.array("Points", 0).empty());
        CHECK(P.array("offsets", 0).empty());
    }
}

TEST_CASE("vtp points: mixing points with and without block ids is an error", "[vtp]") {
    meshless::test::TempDir d("vtp-mixed");
    VtpPointWriter w((d / "m.vtp").string(), {});
    const std::vector<PointRecord> pts{point(0), point(1)};
    const std::vector<std::uint32_t> ids{0, 1};
    w.append(pts, ids);
    CHECK_THROWS_AS(w.append(pts), FormatError);
    CHECK_THROWS_AS(w.append(pts, std::vector<std::uint32_t>{1}), FormatError);
}

TEST_CASE("vtp: a writer that does not commit leaves nothing, a bad path is an IoError", "[vtp]") {
    meshless::test::TempDir d("vtp-atomic");
    {
        VtpPointWriter w((d / "a.vtp").string(), {});
        w.append(std::vector<PointRecord>{point(0)});
    }
    CHECK(fs::is_empty(d.path));
    // an existing file survives an abandoned rewrite
    {
        std::ofstream((d / "keep.vtp").string()) << "old";
    }
    {
        VtpPointWriter w((d / "keep.vtp").string(), {});
        w.append(std::vector<PointRecord>{point(0)});
    }
    CHECK(slurp(d / "keep.vtp") == "old");
    CHECK(std::distance(fs::directory_iterator(d.path), fs::directory_iterator{}) == 1);
    CHECK_THROWS_AS(VtpPointWriter((d / "no" / "such" / "dir.vtp").string(), {}), IoError);
    CHECK_THROWS_AS(write_vtp_mesh(Mesh{}, (d / "no" / "m.vtp").string()), IoError);
}

TEST_CASE("vtp points: memory does not grow with the point count (10^6 points)", "[vtp][memory]") {
    meshless::test::TempDir d("vtp-memory");
    std::vector<PointRecord> batch(65536);
    std::vector<std::uint32_t> ids(batch.size());
    auto run = [&](std::uint64_t n) {
        VtpPointWriter w((d / "m.vtp").string(), {});
        for (std::uint64_t i = 0; i < n; i += batch.size()) {
            const std::size_t k = static_cast<std::size_t>(std::min<std::uint64_t>(batch.size(), n - i));
            for (std::size_t j = 0; j < k; ++j) {
                batch[j] = point(i + j);
                ids[j] = static_cast<std::uint32_t>(j & 3);
            }
            w.append(std::span(batch.data(), k), std::span(ids.data(), k));
        }
        w.commit();
        return w.count();
    };
    run(100000);  // warm up the allocator
    auto grown = [&](std::uint64_t n) {
        {
            std::ofstream("/proc/self/clear_refs") << "5";  // reset VmHWM
        }
        const long before = peak_rss_kib();
        REQUIRE(run(n) == n);
        return peak_rss_kib() - before;
    };
    if (peak_rss_kib() < 0) {
        WARN("no VmHWM in /proc/self/status: memory test skipped");
        return;
    }
    const long small = grown(100000), big = grown(1000000);
    INFO("peak RSS grew by " << small << " KiB writing 10^5 points, " << big << " KiB writing 10^6 points (" << 1000000 * 36 / 1024
                             << " KiB of data)");
    // holding the arrays would take 35 MiB more for 10^6 points; the spools need a few MiB of buffers
    // (the allocator's high-water mark varies by a few MiB between runs: 8 MiB of slack, a quarter of 35)
    CHECK(big < small + 8192);
#ifndef MESHLESS_SANITIZED
    CHECK(big < 12 * 1024);  // (under ASan the first run's growth is shadow memory and quarantine: only the difference counts)
#endif
    CHECK(parse(d / "m.vtp").points == 1000000);
}

TEST_CASE("vtp mesh: polygons, normals and per-cell block ids round trip", "[vtp][mc]") {
    meshless::test::TempDir d("vtp-mesh");
    const Volume v = make_analytic_volume(AnalyticField::torus, 24);
    Mesh m = marching_cubes(v.view(), default_iso(AnalyticField::torus));
    REQUIRE(m.triangle_count() > 100);
    for (const bool blocks : {false, true}) {
        INFO("blocks " << blocks);
        m.block.clear();
        if (blocks)
            for (std::size_t t = 0; t < m.triangle_count(); ++t) m.block.push_back(static_cast<std::uint32_t>(t % 3));
        VtpOptions o;
        o.block_size = 5000;
        write_vtp_mesh(m, (d / "m.vtp").string(), {"mesh"}, o);
        const Parsed P = parse(d / "m.vtp");
        const std::uint64_t nv = m.vertex_count(), nf = m.triangle_count();
        CHECK(P.points == nv);
        CHECK(P.polys == nf);
        CHECK(P.verts == 0);
        const auto xyz = P.array("Points", 3 * nv), nrm = P.array("Normals", 3 * nv), conn = P.array("connectivity", 3 * nf),
                   offs = P.array("offsets", nf);
        for (std::size_t i = 0; i < 3 * nv; ++i) {
            REQUIRE(xyz[i] == static_cast<double>(m.xyz[i]));
            REQUIRE(nrm[i] == static_cast<double>(m.normals[i]));
        }
        for (std::size_t i = 0; i < 3 * nf; ++i) REQUIRE(conn[i] == static_cast<double>(m.tri[i]));
        for (std::size_t t = 0; t < nf; ++t) REQUIRE(offs[t] == static_cast<double>(3 * (t + 1)));
        CHECK(P.has("block") == blocks);
        if (blocks) {
            CHECK(P.doc.find("<CellData Scalars=\"block\">") != std::string::npos);
            const auto b = P.array("block", nf);
            for (std::size_t t = 0; t < nf; ++t) REQUIRE(b[t] == static_cast<double>(t % 3));
        }
    }
    // without normals: no PointData
    m.normals.clear();
    m.block.clear();
    write_vtp_mesh(m, (d / "n.vtp").string());
    CHECK(slurp(d / "n.vtp").find("<PointData") == std::string::npos);
    // inconsistent meshes are refused before anything is written
    Mesh bad = m;
    bad.tri.push_back(static_cast<std::uint32_t>(m.vertex_count()));
    bad.tri.push_back(0);
    bad.tri.push_back(0);
    CHECK_THROWS_AS(write_vtp_mesh(bad, (d / "bad.vtp").string()), std::invalid_argument);
    CHECK_FALSE(fs::exists(d / "bad.vtp"));
}

TEST_CASE("vtp points: the bytes depend on the points only, not on batching or compressing threads", "[vtp]") {
    meshless::test::TempDir d("vtp-batches");
    std::vector<PointRecord> pts;
    for (std::uint64_t i = 0; i < 30000; ++i) {
        PointRecord p = point(i);
        if ((i / 3000) % 2) {  // grid-aligned stretches, where zlib's string matching pays: both strategies occur
            p.pos[0] = std::round(p.pos[0]);
            p.pos[1] = std::round(p.pos[1]);
        }
        pts.push_back(p);
    }
    VtpOptions o;
    o.block_size = 4096;
    auto write = [&](const std::string& name, std::size_t step) {
        VtpPointWriter w((d / name).string(), {"c"}, o);
        for (std::size_t i = 0; i < pts.size(); i += step)
            w.append(std::span(pts.data() + i, std::min(step, pts.size() - i)));
        w.commit();
        return slurp(d / name);
    };
    o.threads = 1;
    const std::string one = write("one.vtp", pts.size()), small = write("small.vtp", 77);
    o.threads = 4;
    const std::string odd = write("odd.vtp", 4097), big = write("big.vtp", pts.size());
    CHECK(one == small);
    CHECK(one == odd);
    CHECK(one == big);
    const Parsed P = parse(d / "one.vtp");
    const auto xyz = P.array("Points", 3 * pts.size());
    for (std::size_t i = 0; i < pts.size(); ++i) REQUIRE(xyz[3 * i] == static_cast<double>(pts[i].pos[0]));
}
