// Tests for formats/ply_mesh.hpp. Oracles: write/read round trips (bit-identical arrays), a
// hand-written ASCII file, every truncation of a valid binary file, corrupted headers and indices.
#include <catch2/catch.hpp>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "../test_paths.hpp"
#include "formats/ply_mesh.hpp"
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
void spit(const fs::path& p, const std::string& s) {
    std::ofstream out(p, std::ios::binary | std::ios::trunc);
    out.write(s.data(), static_cast<std::streamsize>(s.size()));
}

Mesh small_mesh() {
    const Volume v = make_analytic_volume(AnalyticField::torus, 20);
    return marching_cubes(v.view(), default_iso(AnalyticField::torus));
}

}  // namespace

TEST_CASE("ply mesh: binary round trip is exact", "[mc]") {
    test::TempDir dir("plymesh");
    const Mesh m = small_mesh();
    REQUIRE(m.triangle_count() > 100);
    const std::string path = (dir / "torus.ply").string();
    write_ply_mesh(m, path);
    const Mesh r = read_ply_mesh(path);
    CHECK(r.xyz == m.xyz);
    CHECK(r.normals == m.normals);
    CHECK(r.tri == m.tri);
    // the file has exactly the documented layout: header + 24 B per vertex + 13 B per face
    const std::string bytes = slurp(path);
    const std::size_t header = bytes.find("end_header\n") + 11;
    CHECK(bytes.size() == header + 24 * m.vertex_count() + 13 * m.triangle_count());
    // no temporary left behind
    std::size_t files = 0;
    for (auto& e : fs::directory_iterator(dir.path)) (void)e, ++files;
    CHECK(files == 1);

    // without normals
    Mesh bare = m;
    bare.normals.clear();
    write_ply_mesh(bare, path);
    const Mesh rb = read_ply_mesh(path);
    CHECK(rb.xyz == m.xyz);
    CHECK(rb.normals.empty());
    CHECK(rb.tri == m.tri);

    // empty mesh
    write_ply_mesh(Mesh{}, path);
    const Mesh re = read_ply_mesh(path);
    CHECK(re.vertex_count() == 0);
    CHECK(re.triangle_count() == 0);
}

TEST_CASE("ply mesh: ASCII with extra properties, elements and a quad", "[mc]") {
    test::TempDir dir("plymesh-ascii");
    const auto path = dir / "quad.ply";
    spit(path,
         "ply\r\nformat ascii 1.0\r\ncomment hand written\r\nelement vertex 4\r\n"
         "property double x\r\nproperty double y\r\nproperty double z\r\nproperty uchar red\r\n"
         "element face 1\r\nproperty list uchar uint vertex_indices\r\nproperty float quality\r\n"
         "element edge 1\r\nproperty int vertex1\r\nproperty int vertex2\r\nend_header\r\n"
         "0 0 0 255\n1 0 0 0\n1 1 0 1\n0 1 0.5 2\n4 0 1 2 3 0.25\n0 1\n");
    const Mesh m = read_ply_mesh(path.string());
    REQUIRE(m.vertex_count() == 4);
    CHECK(m.normals.empty());
    CHECK(m.xyz[9 + 2] == 0.5f);
    CHECK(m.tri == std::vector<std::uint32_t>{0, 1, 2, 0, 2, 3});  // fan
}

TEST_CASE("ply mesh: truncated and corrupted files fail with FormatError", "[mc]") {
    test::TempDir dir("plymesh-bad");
    const auto good = dir / "good.ply";
    const auto bad = dir / "bad.ply";
    Mesh m;
    m.xyz = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
    m.normals = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
    m.tri = {0, 1, 2, 0, 2, 3, 0, 3, 1, 1, 3, 2};
    write_ply_mesh(m, good.string());
    const std::string bytes = slurp(good);
    const std::size_t header = bytes.find("end_header\n") + 11;
    // every truncation, inside the header and inside the body
    for (std::size_t len = 0; len < bytes.size(); ++len) {
        INFO("length " << len);
        spit(bad, bytes.substr(0, len));
        CHECK_THROWS_AS(read_ply_mesh(bad.string()), FormatError);
    }
    // an index out of range (last index of the last face)
    {
        std::string b = bytes;
        const std::int32_t big = 4;
        std::memcpy(&b[b.size() - 4], &big, 4);
        spit(bad, b);
        CHECK_THROWS_AS(read_ply_mesh(bad.string()), FormatError);
    }
    const std::string body = bytes.substr(header);
    const std::string cases[] = {
        "garbage\x01\x02",
        "ply\nformat binary_big_endian 1.0\nelement vertex 0\nproperty float x\nend_header\n",
        "ply\nformat binary_little_endian 2.0\nend_header\n",
        "ply\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\nend_header\n",
        "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nend_header\n1 2\n",
        "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\nend_header\n1 2 zz\n",
        "ply\nformat ascii 1.0\nelement vertex 1\nproperty fancy x\nend_header\n",
        "ply\nformat ascii 1.0\nelement vertex -1\nproperty float x\nend_header\n",
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
        "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0 1 0 0 0 1 0\n3 0 1 -1\n",
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
        "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0 1 0 0 0 1 0\n2 0 1\n",
        "ply\nformat ascii 1.0\nbogus line\nend_header\n",
    };
    for (const std::string& c : cases) {
        INFO(c);
        spit(bad, c);
        CHECK_THROWS_AS(read_ply_mesh(bad.string()), FormatError);
    }
    CHECK_THROWS_AS(read_ply_mesh((dir / "missing.ply").string()), IoError);
}

TEST_CASE("ply mesh: inconsistent meshes are refused by the writer", "[mc]") {
    test::TempDir dir("plymesh-w");
    Mesh m;
    m.xyz = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    m.tri = {0, 1, 3};
    CHECK_THROWS_AS(write_ply_mesh(m, (dir / "a.ply").string()), std::invalid_argument);
    m.tri = {0, 1, 2};
    m.normals = {0, 0, 1};
    CHECK_THROWS_AS(write_ply_mesh(m, (dir / "a.ply").string()), std::invalid_argument);
    CHECK_FALSE(fs::exists(dir / "a.ply"));
    CHECK_THROWS_AS(write_ply_mesh(small_mesh(), dir.path.string()), IoError);  // a directory
}

TEST_CASE("ply mesh: per-face block ids round trip, bad ones are refused", "[mc][block_mc]") {
    meshless::test::TempDir dir("plymesh-block");
    Mesh m = small_mesh();
    m.block.resize(m.triangle_count());
    for (std::size_t t = 0; t < m.block.size(); ++t) m.block[t] = static_cast<std::uint32_t>(t * 2654435761u % 7u) + (t == 0 ? 4000000000u : 0u);
    const auto path = (dir / "b.ply").string();
    write_ply_mesh(m, path);
    CHECK(slurp(path).find("property uint block\n") != std::string::npos);
    const Mesh r = read_ply_mesh(path);
    CHECK(r.block == m.block);
    CHECK(r.tri == m.tri);
    // a mesh without ids writes no property and reads back without ids
    Mesh plain = small_mesh();
    write_ply_mesh(plain, path);
    CHECK(slurp(path).find("block") == std::string::npos);
    CHECK(read_ply_mesh(path).block.empty());
    // ids of another count than the triangles
    m.block.pop_back();
    CHECK_THROWS_AS(write_ply_mesh(m, path), std::invalid_argument);
    // ASCII: a quad gets its id twice; a negative, fractional or list id is refused
    const std::string head = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n";
    const std::string verts = "0 0 0\n1 0 0\n1 1 0\n0 1 0\n";
    spit(dir / "q.ply", head + "element face 1\nproperty list uchar int vertex_indices\nproperty int block\nend_header\n" + verts + "4 0 1 2 3 5\n");
    CHECK(read_ply_mesh((dir / "q.ply").string()).block == std::vector<std::uint32_t>{5, 5});
    for (const char* bad : {"4 0 1 2 3 -1\n", "4 0 1 2 3 2.5\n"}) {
        spit(dir / "q.ply", head + "element face 1\nproperty list uchar int vertex_indices\nproperty float block\nend_header\n" + verts + bad);
        CHECK_THROWS_AS(read_ply_mesh((dir / "q.ply").string()), FormatError);
    }
    spit(dir / "q.ply", head + "element face 1\nproperty list uchar int vertex_indices\nproperty list uchar int block\nend_header\n" + verts +
                            "4 0 1 2 3 1 7\n");
    CHECK_THROWS_AS(read_ply_mesh((dir / "q.ply").string()), FormatError);
}

TEST_CASE("ply mesh: face indices that are no vertex index are refused with the value shown", "[mc]") {
    // float index lists: NaN, huge, negative and fractional values are each a FormatError that quotes
    // the value (the message used to convert it to an integer first: undefined for NaN and 1e30)
    meshless::test::TempDir dir("ply_mesh_bad_index");
    const std::string head =
        "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
        "element face 1\nproperty list uchar float vertex_indices\nend_header\n";
    const float verts[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    for (const auto& [v, shown] : std::vector<std::pair<float, std::string>>{
             {std::numeric_limits<float>::quiet_NaN(), "index nan out"}, {1e30f, "index 1.0000000150474662e+30 out"},
             {-5.0f, "index -5 out"}, {1.5f, "index 1.5 out"}, {3.0f, "index 3 out"}}) {
        std::string body(reinterpret_cast<const char*>(verts), sizeof verts);
        body += '\x03';
        const float idx[3] = {0, 1, v};
        body.append(reinterpret_cast<const char*>(idx), sizeof idx);
        const auto path = (dir.path / "bad.ply").string();
        spit(path, head + body);
        INFO(shown);
        CHECK_THROWS_WITH(read_ply_mesh(path), Catch::Contains(shown) && Catch::Contains("(3 vertices)"));
    }
}
