// VolumeInput::blocks() (stream/volume_input.hpp): the one pass that gives the value range and the surface
// frame. Split into layers of blocks across threads (each thread with its own reader of a raw
// payload, or straight from memory), it gives exactly the blocks of the serial pass and of
// block_minmax on the whole volume, for any thread count; a gzip payload (no reopen) stays serial.
#include <zlib.h>

#include <catch2/catch.hpp>

#include <algorithm>
#include <filesystem>
#include <random>
#include <string>

#include "cli/cli_harness.hpp"
#include "stream/volume_input.hpp"
#include "formats/volume_reader.hpp"
#include "kernels/block_minmax.hpp"

using namespace meshless;
using namespace meshless::test;
namespace fs = std::filesystem;

TEST_CASE("VolumeInput::blocks: the same blocks for any thread count, streamed or in memory", "[cli][blocks]") {
    TempDir d("blocks");
    // 70 x 50 x 99: three full layers of 32-cell blocks and a partial one; random bytes with a
    // bright corner so that blocks differ
    std::string bytes(70 * 50 * 99, '\0');
    std::mt19937 rng(4);
    for (std::size_t i = 0; i < bytes.size(); ++i) bytes[i] = static_cast<char>(rng() % 200);
    bytes[bytes.size() - 1] = static_cast<char>(255);
    const std::string path = (d / "v_70x50x99_uint8.raw").string();
    spit(path, bytes);
    const Volume whole = read_volume(path);
    const BlockMinMax want = block_minmax(whole.view(), 32);
    REQUIRE(want.blocks[2] == 4);
    for (int threads : {1, 2, 3, 8}) {
        INFO("threads " << threads);
        VolumeInput streamed;
        streamed.slices = open_slice_source(path);
        streamed.reopen = [&] { return open_slice_source(path); };
        streamed.threads = threads;
        VolumeInput serial;  // no reopen: read in order whatever the thread count
        serial.slices = open_slice_source(path);
        serial.threads = threads;
        VolumeInput memory;
        memory.volume = read_volume(path);
        memory.threads = threads;
        for (const VolumeInput* in : {&streamed, &serial, &memory}) {
            const BlockMinMax& got = in->blocks();
            CHECK(got.blocks == want.blocks);
            CHECK(got.vmin == want.vmin);
            CHECK(got.vmax == want.vmax);
            CHECK(in->value_range()[1] == 255);
        }
    }
}

namespace {
// A gzip member holding `n` zero bytes (written in pieces: no n-byte buffer).
std::string gzip_zeros(std::size_t n) {
    z_stream zs{};
    REQUIRE(deflateInit2(&zs, 9, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY) == Z_OK);
    const std::string chunk(1 << 16, '\0');
    std::string out;
    char buf[1 << 14];
    for (std::size_t left = n;;) {
        const std::size_t k = std::min(left, chunk.size());
        zs.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(chunk.data()));
        zs.avail_in = static_cast<uInt>(k);
        left -= k;
        const int flush = left == 0 ? Z_FINISH : Z_NO_FLUSH;
        int r;
        do {
            zs.next_out = reinterpret_cast<Bytef*>(buf);
            zs.avail_out = sizeof buf;
            r = deflate(&zs, flush);
            out.append(buf, sizeof buf - zs.avail_out);
        } while (zs.avail_out == 0);
        if (flush == Z_FINISH) {
            REQUIRE(r == Z_STREAM_END);
            break;
        }
    }
    deflateEnd(&zs);
    return out;
}
}  // namespace

TEST_CASE("a volume read whole is checked against --memory (or the memory this process may use) before it is read",
          "[cli][memory]") {
    TempDir d("memcheck");
    const std::string D = d.path.string();
    // 128^3 uint8 = 2 MiB decoded from a few KiB of gzip: a volume `mc` reads whole
    spit(d / "g.nrrd", "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 128 128 128\nencoding: gzip\n\n" + gzip_zeros(128 * 128 * 128));
    auto r = sh("MESHLESS mc " + D + "/g.nrrd --iso 0.5 -o " + D + "/m.ply --memory 1M", d);
    CHECK(r.code == 2);
    CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
    CHECK(r.err.find("g.nrrd") != std::string::npos);
    CHECK(r.err.find("2.0 MiB") != std::string::npos);
    CHECK(r.err.find("--memory 1.0 MiB") != std::string::npos);
    CHECK(r.err.find("meshless convert") != std::string::npos);
    CHECK(!fs::exists(d / "m.ply"));
    // within the budget, and without --memory (the machine's memory): read as before
    CHECK(sh("MESHLESS mc " + D + "/g.nrrd --iso 0.5 -o " + D + "/m.ply --memory 3M", d).code == 0);
    CHECK(sh("MESHLESS mc " + D + "/g.nrrd --iso 0.5 -o " + D + "/m2.ply", d).code == 0);
    // a raw file is mapped, not copied: it costs no memory of its own and passes any --memory
    spit(d / "r_128x128x128_uint8.raw", std::string(128 * 128 * 128, '\0'));
    CHECK(sh("MESHLESS mc " + D + "/r_128x128x128_uint8.raw --iso 0.5 -o " + D + "/r.ply --memory 1M", d).code == 0);
    // a header claiming 2 TiB is refused up front without --memory (before its payload is even
    // looked at), naming what this process may use
    spit(d / "huge.nrrd", "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 16384 16384 8192\nencoding: gzip\n\n" + gzip_zeros(1 << 20));
    r = sh("MESHLESS mc " + D + "/huge.nrrd --iso 0.5 -o " + D + "/h.ply", d);
    CHECK(r.code == 2);
    CHECK(r.err.find("huge.nrrd") != std::string::npos);
    CHECK(r.err.find("2.0 TiB") != std::string::npos);
    CHECK(r.err.find("this process may use") != std::string::npos);
    CHECK(r.err.find("meshless convert") != std::string::npos);
    // a VTI (never mapped) against --memory, through a command that otherwise streams its input
    const std::string vti = "<?xml version=\"1.0\"?>\n<VTKFile type=\"ImageData\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
                            "<ImageData WholeExtent=\"0 1 0 1 0 1\" Origin=\"0 0 0\" Spacing=\"1 1 1\">\n<Piece Extent=\"0 1 0 1 0 1\">\n"
                            "<PointData Scalars=\"s\">\n<DataArray type=\"Float64\" Name=\"s\" format=\"ascii\">\n"
                            "0 1 2 3 4 5 6 7\n</DataArray>\n</PointData>\n</Piece>\n</ImageData>\n</VTKFile>\n";
    spit(d / "v.vti", vti);
    r = sh("MESHLESS isosurface " + D + "/v.vti --iso 3.5 -o " + D + "/v.ply --memory 16", d);
    CHECK(r.code == 2);
    CHECK(r.err.find("v.vti") != std::string::npos);
    CHECK(r.err.find("32 bytes") != std::string::npos);  // float64 samples are read as float32
    CHECK(sh("MESHLESS isosurface " + D + "/v.vti --iso 3.5 -o " + D + "/v.ply --memory 1K", d).code == 0);
}
