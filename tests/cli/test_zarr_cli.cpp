// Zarr v2 stores through the volume commands (formats/zarr.hpp): the tooth CT written as Zarr stores
// (tests/zarr_test_data.hpp: zlib, zstd, blosc, none; C and F order; both separators; OME-Zarr level 0
// with scale 1) gives the raw file's isosurface points, mc mesh and convert brick store byte for byte
// (less the PLY comment naming the input); info describes the store; --spacing applies to a plain
// store and is ignored, with a warning, by an OME-Zarr image that gives its scale; and each defect
// class is refused with one line naming the file and exit 2.
#include <catch2/catch.hpp>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "cli/cli_harness.hpp"
#include "test_paths.hpp"
#include "zarr_test_data.hpp"

using namespace meshless;
using namespace meshless::test;

namespace {

const std::string& kTooth = kToothRaw;

}  // namespace

TEST_CASE("zarr stores: isosurface, mc and convert give the raw file's bytes, info describes the store", "[cli][zarr]") {
    if (!std::filesystem::exists(kTooth)) {
        WARN("skipped: " << kTooth << " is absent");
        return;
    }
    TempDir d("zarr-cli");
    const std::string D = d.path.string() + "/";
    const std::string bytes = slurp(kTooth);
    std::vector<double> values(bytes.begin(), bytes.end());
    for (double& v : values) v = static_cast<unsigned char>(static_cast<char>(v));
    struct Store {
        std::string name;
        ZarrWriteOptions o;
        bool ome = false;
    };
    std::vector<Store> stores;
    {
        Store s{"zlib.zarr", {}, false};
        s.o.compressor = "zlib";
        s.o.chunks = {32, 40, 48};  // none divides 161 x 94 x 103
        stores.push_back(s);
        s = {"zstdF.zarr", {}, false};
        s.o.compressor = "zstd";
        s.o.fortran = true;
        s.o.separator = '/';
        s.o.chunks = {50, 94, 64};
        stores.push_back(s);
        s = {"blosc.zarr", {}, false};
        s.o.compressor = "blosc";
        s.o.chunks = {16, 16, 16};
        stores.push_back(s);
        s = {"none.zarr", {}, false};
        s.o.chunks = {161, 94, 103};  // one chunk
        stores.push_back(s);
        s = {"img.ome.zarr", {}, true};
        s.o.compressor = "gzip";
        s.o.leading = {1};
        s.o.chunks = {64, 64, 64};
        stores.push_back(s);
    }
    for (const Store& s : stores) {
        if (s.ome) write_ome_zarr(d.path / s.name, values, 103, 94, 161, {1, 1, 1}, {0, 0, 0}, s.o);
        else write_zarr(d.path / s.name, values, 103, 94, 161, s.o);
    }
    struct Cmd {
        std::string args, out;
    };
    const Cmd cmds[] = {
        {"isosurface IN --iso 100.5 -o OUT", "i.ply"},
        {"isosurface IN --iso 60.5 --threads 2 -o OUT", "t.ply"},
        {"mc IN --iso 100.5 -o OUT", "m.ply"},
        {"convert IN -o OUT", "c.mlb"},
    };
    for (const Cmd& c : cmds) {
        std::string line = "MESHLESS " + c.args;
        line.replace(line.find("IN"), 2, kTooth);
        line.replace(line.find("OUT"), 3, D + "raw" + c.out);
        const RunResult r = sh(line, d);
        INFO(line << ": " << r.err);
        REQUIRE(r.code == 0);
        const std::string want = slurp(D + "raw" + c.out);
        REQUIRE(!want.empty());
        for (const Store& s : stores) {
            std::string zl = "MESHLESS " + c.args;
            zl.replace(zl.find("IN"), 2, D + s.name);
            zl.replace(zl.find("OUT"), 3, D + s.name + c.out);
            const RunResult z = sh(zl, d);
            INFO(zl << ": " << z.err);
            REQUIRE(z.code == 0);
            CHECK(z.err.find("warning") == std::string::npos);
            const std::string got = slurp(D + s.name + c.out);
            if (c.out == "c.mlb") CHECK(got.size() == want.size());  // a PLY's comment names its input
            if (c.out == "c.mlb" && s.ome) {  // its axes say micrometres: the header records them (byte 232, then its CRC)
                CHECK(static_cast<unsigned char>(got[232]) == 3);
                CHECK(got.substr(0, 232) == want.substr(0, 232));
                CHECK(got.substr(256) == want.substr(256));
                continue;
            }
            CHECK(without_tooth_names(got) == without_tooth_names(want));
        }
    }
    const RunResult info = sh("MESHLESS info " + D + "zlib.zarr", d);
    INFO(info.err);
    REQUIRE(info.code == 0);
    CHECK(info.out.find("zlib.zarr: zarr volume") != std::string::npos);
    CHECK(info.out.find("dims: 103 x 94 x 161") != std::string::npos);
    CHECK(info.out.find("encoding: Zarr v2, shape (161, 94, 103) order C, dtype |u1, chunks (32, 40, 48) (54 chunk files, "
                        "separator '.'), compressor zlib level 6, fill_value 0") != std::string::npos);
    CHECK(info.out.find("spacing: 1 1 1") != std::string::npos);
    const RunResult ome = sh("MESHLESS info " + D + "img.ome.zarr", d);
    CHECK(ome.code == 0);
    CHECK(ome.out.find("ome-zarr volume") != std::string::npos);
    CHECK(ome.out.find("level 0 \"0\"") != std::string::npos);
    CHECK(ome.out.find("length unit: um") != std::string::npos);  // its axes' "micrometer"
    CHECK(info.out.find("length unit") == std::string::npos);     // a plain store says nothing
    // --spacing: a plain store takes it; an OME-Zarr image with a scale ignores it and says so
    const RunResult sp = sh("MESHLESS info " + D + "zlib.zarr --spacing 0.5,1,2", d);
    CHECK(sp.out.find("spacing: 0.5 1 2") != std::string::npos);
    const RunResult so = sh("MESHLESS isosurface " + D + "img.ome.zarr --iso 100.5 --spacing 0.5,1,2 -o " + D + "w.ply", d);
    CHECK(so.code == 0);
    CHECK(so.err.find("--spacing is ignored") != std::string::npos);
    // one array: --array names nothing to choose (a usage error, exit 1)
    const RunResult arr = sh("MESHLESS isosurface " + D + "zlib.zarr --iso 100.5 --array a -o " + D + "w.ply", d);
    CHECK(arr.code == 1);
    CHECK(arr.err.find("zlib.zarr: a zarr volume holds one unnamed array: no array 'a' to choose") != std::string::npos);
    // --resolution-level: an OME-Zarr image's level 1 (the writer's: constant, so no surface), beyond
    // its levels and on a plain store a usage error (exit 1)
    const RunResult l1 = sh("MESHLESS info " + D + "img.ome.zarr --resolution-level 1", d);
    CHECK(l1.code == 0);
    CHECK(l1.out.find("level 1 \"1\" of 2") != std::string::npos);
    CHECK(l1.out.find("dims: 52 x 47 x 81") != std::string::npos);
    const RunResult l5 = sh("MESHLESS isosurface " + D + "img.ome.zarr --resolution-level 5 --iso 100.5 -o " + D + "w.ply", d);
    CHECK(l5.code == 1);
    CHECK(l5.err.find("resolution level 5 asked, the image has 2") != std::string::npos);
    const RunResult lp = sh("MESHLESS convert " + D + "zlib.zarr --resolution-level 1 -o " + D + "w.mlb", d);
    CHECK(lp.code == 1);
    CHECK(lp.err.find("a Zarr array has one resolution") != std::string::npos);
}

TEST_CASE("zarr stores: each defect class is refused with one line naming the file and exit 2", "[cli][zarr]") {
    TempDir d("zarr-cli-bad");
    const std::string D = d.path.string() + "/";
    auto zarray = [](const std::string& shape, const std::string& dtype, const std::string& compressor, const std::string& more) {
        return "{\"zarr_format\": 2, \"shape\": " + shape + ", \"chunks\": [2, 4, 4], \"dtype\": \"" + dtype +
               "\", \"compressor\": " + compressor + ", \"fill_value\": 0, \"filters\": " + more + ", \"order\": \"C\"}";
    };
    const std::string zlib = "{\"id\": \"zlib\", \"level\": 1}";
    struct Bad {
        std::string name, zarray, chunk, message;
    };
    const Bad bad[] = {
        {"json", "{\"zarr_format\": 2,", "", "json.zarr/.zarray: bad JSON"},
        {"dtype", zarray("[2, 4, 4]", "<c8", "null", "null"), "", "dtype.zarr/.zarray: dtype \"<c8\" is not read"},
        {"format", "{\"zarr_format\": 1}", "", "format.zarr/.zarray: zarr_format 1 is not read (Zarr v2 stores are)"},
        {"shape", zarray("[4, 4]", "|u1", "null", "null"), "", "shape.zarr/.zarray: chunks (2, 4, 4) do not have one entry per axis of shape (4, 4)"},
        {"twod", "{\"zarr_format\": 2, \"shape\": [4, 4], \"chunks\": [4, 4], \"dtype\": \"|u1\", \"compressor\": null, \"fill_value\": 0, \"filters\": null, \"order\": \"C\"}",
         "", "twod.zarr/.zarray: shape (4, 4) is not a volume"},
        {"size", zarray("[2, 4, 4]", "|u1", zlib, "null"), zarr_compress(std::string(31, '\x01'), "zlib", 1),
         "size.zarr/0.0.0: compressed data ends after 31 decompressed bytes, expected 32"},
        {"truncated", zarray("[2, 4, 4]", "|u1", "null", "null"), std::string(20, '\x01'),
         "truncated.zarr/0.0.0: uncompressed chunk of 20 bytes, expected 32"},
        {"bomb", zarray("[2, 4, 4]", "|u1", zlib, "null"), zarr_compress(std::string(std::size_t{16} << 20, '\0'), "zlib", 1),
         "is larger than a chunk of 32 bytes compresses to (zlib level 1)"},
        {"filters", zarray("[2, 4, 4]", "|u1", "null", "[{\"id\": \"shuffle\"}]"), "", "filters.zarr/.zarray: filters [\"shuffle\"] are not supported"},
        {"negative", zarray("[2, -4, 4]", "|u1", "null", "null"), "", "negative.zarr/.zarray: \"shape\"[1] -4 is not an integer"},
        {"overflow", zarray("[4294967296, 4294967296, 4294967296]", "|u1", "null", "null"), "", "size overflow"},
    };
    for (const Bad& b : bad) {
        const auto dir = d.path / (b.name + ".zarr");
        zarr_put(dir / ".zarray", b.zarray);
        if (!b.chunk.empty()) zarr_put(dir / "0.0.0", b.chunk);
        for (const std::string cmd : {"isosurface " + dir.string() + " --iso 1 -o " + D + "x.ply", "info " + dir.string()}) {
            const RunResult r = sh("MESHLESS " + cmd, d);
            INFO(cmd << ": " << r.err);
            CHECK(r.code == 2);
            CHECK(r.err.find(b.message) != std::string::npos);
            CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
        }
    }
}

TEST_CASE("zarr stores written by zarr-python read as the raw file (skipped without python3-zarr)", "[cli][zarr]") {
    if (!std::filesystem::exists(kTooth)) {
        WARN("skipped: " << kTooth << " is absent");
        return;
    }
    TempDir d("zarr-python");
    const std::string D = d.path.string() + "/";
    if (sh("/usr/bin/python3 -c \"import zarr, numpy\"", d).code != 0) {
        WARN("skipped: /usr/bin/python3 cannot import zarr (Debian python3-zarr)");
        return;
    }
    // zarr-python's defaults (Blosc lz4 with shuffle, guessed chunks), an F-order zstd store of
    // (nx, ny, nz) with nested chunk folders, and all-zero chunks left out (zarr-python's default)
    spit(d.path / "gen.py",
         "import numpy as np, zarr, numcodecs\n"
         "v = np.fromfile(\"" + kTooth + "\", np.uint8).reshape(161, 94, 103)\n"
         "zarr.save_array(\"" + D + "default.zarr\", v)\n"
         "z = zarr.open_array(\"" + D + "f.zarr\", mode=\"w\", shape=(103, 94, 161), chunks=(40, 40, 40), dtype=\">u2\",\n"
         "                    order=\"F\", compressor=numcodecs.Zstd(level=1), dimension_separator=\"/\")\n"
         "z[:] = v.T.astype(\">u2\")\n"
         "w = np.where(np.arange(161)[:, None, None] < 64, 0, v).astype(np.uint8)\n"
         "zarr.save_array(\"" + D + "sparse.zarr\", w, chunks=(32, 94, 103), compressor=numcodecs.Zlib(level=1),\n"
         "                write_empty_chunks=False)\n"
         "w.tofile(\"" + D + "sparse_103x94x161_uint8.raw\")\n");
    const RunResult gen = sh("/usr/bin/python3 " + D + "gen.py", d);
    INFO(gen.err);
    REQUIRE(gen.code == 0);
    CHECK(!std::filesystem::exists(d.path / "sparse.zarr" / "0.0.0"));  // all zero: not written
    struct Pair {
        std::string raw, store;
    };
    for (const Pair& p : {Pair{kTooth, "default.zarr"}, Pair{kTooth, "f.zarr"}, Pair{D + "sparse_103x94x161_uint8.raw", "sparse.zarr"}}) {
        std::string out[2];
        for (int k = 0; k < 2; ++k) {
            const std::string line = "MESHLESS isosurface " + (k ? D + p.store : p.raw) + " --iso 100.5 -o " + D + std::to_string(k) + ".ply";
            const RunResult r = sh(line, d);
            INFO(line << ": " << r.err);
            REQUIRE(r.code == 0);
            out[k] = without_tooth_names(slurp(D + std::to_string(k) + ".ply"));
        }
        INFO(p.store);
        CHECK(out[0] == out[1]);
    }
}
