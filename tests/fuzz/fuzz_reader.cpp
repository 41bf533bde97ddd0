// One libFuzzer source, built once per decoder (tests/fuzz/CMakeLists.txt: fuzz_nrrd, fuzz_mha,
// fuzz_vtk_legacy, fuzz_vti, fuzz_vtkjs, fuzz_slc, fuzz_nifti, fuzz_nifti_gz, fuzz_voreen, fuzz_npy_volume,
// fuzz_raw_sidecar, fuzz_dicom, fuzz_plot3d, fuzz_vtp, fuzz_oriented_vtp, fuzz_vts, fuzz_vtu, fuzz_csv, fuzz_npy, fuzz_points_raw, fuzz_point_stream, fuzz_mlb,
// fuzz_mls, fuzz_positions, fuzz_zarr, fuzz_hdf5). Compile definitions pick the decoder:
//   FUZZ_KIND   1 volume (read_volume + probe_volume), 2 point set (read_point_set + probe), 3 the
//               binary point/sample stream (StreamReader), 4 a brick store .mlb (open + verify),
//               5 a sample store .mls (open; its .mlb from the second file), 6 a list of
//               positions (read_positions, `probe --at-file`), 7 oriented points (.vtp), 8 a Zarr
//               store (as 1, but a store whose chunks or samples claim more than 64 MiB is only
//               probed: a missing chunk is legitimately its fill value, so a large claim is no defect),
//               9 an HDF5 dataset (the same, for chunks never written)
//   FUZZ_MAIN   the name the input is written under (its extension selects the reader)
//   FUZZ_SECOND optional: a second file; the input is then "MAIN \0 SECOND" (split at the first NUL)
//   FUZZ_READ   optional: the file handed to the reader (default FUZZ_MAIN; fuzz_raw_sidecar reads
//               the raw file whose .dat sidecar is the fuzzed text)
// Files live in one temporary directory per process, rewritten per input. The only acceptable
// failures are the library's FormatError, IoError and InvalidArgument; anything else (a crash, a
// sanitizer report, std::bad_alloc or another exception, an allocation the data does not justify,
// a hang) is a defect. scripts/fuzz.sh builds and runs them all (README "Fuzzing").
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>

#include "kernels/errors.hpp"

#if FUZZ_KIND == 1
#include "formats/volume_reader.hpp"
#elif FUZZ_KIND == 2
#include "formats/point_set_reader.hpp"
#elif FUZZ_KIND == 3
#include "formats/point_stream.hpp"
#elif FUZZ_KIND == 4
#include "ooc/brick_store.hpp"
#include "ooc/verify_brick_store.hpp"
#elif FUZZ_KIND == 5
#include "ooc/sample_store.hpp"
#elif FUZZ_KIND == 6
#include <cmath>

#include "formats/position_list.hpp"
#elif FUZZ_KIND == 7
#include <cmath>

#include "formats/oriented_points_vtp.hpp"
#elif FUZZ_KIND == 8
#include "formats/volume_reader.hpp"
#include "formats/zarr.hpp"
#elif FUZZ_KIND == 9
#include "formats/volume_reader.hpp"
#endif

#ifndef FUZZ_SECOND
#define FUZZ_SECOND ""
#endif
#ifndef FUZZ_READ
#define FUZZ_READ FUZZ_MAIN
#endif

using namespace meshless;

namespace {

const std::filesystem::path& dir() {
    static const std::filesystem::path d = [] {
        auto p = std::filesystem::temp_directory_path() / ("meshless-fuzz-" + std::to_string(::getpid()));
        std::filesystem::create_directories(p);
        return p;
    }();
    return d;
}

std::string put(const std::string& name, std::string_view bytes) {
    const auto p = dir() / name;
    std::filesystem::create_directories(p.parent_path());
    std::ofstream f(p, std::ios::binary | std::ios::trunc);
    f.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    return p.string();
}

void run(const std::string& path) {
#if FUZZ_KIND == 1
    const VolumeInfo i = probe_volume(path);
    const Volume v = read_volume(path);
    // oracle: the volume holds exactly what its grid says, and probing agreed on the grid
    if (v.bytes.size() != static_cast<std::size_t>(v.grid.voxel_count()) * sample_size(v.type)) __builtin_trap();
    if (i.grid.dims != v.grid.dims) __builtin_trap();
#elif FUZZ_KIND == 8
    const ZarrArray a = open_zarr(path);
    const VolumeInfo i = probe_volume(path);
    constexpr std::uint64_t kMax = std::uint64_t{64} << 20;
    if (a.chunk_bytes > kMax || decoded_bytes(i, path) > kMax) return;
    (void)prove_volume(path);
    const Volume v = read_volume(path);
    if (v.bytes.size() != static_cast<std::size_t>(v.grid.voxel_count()) * sample_size(v.type)) __builtin_trap();
    if (i.grid.dims != v.grid.dims) __builtin_trap();
#elif FUZZ_KIND == 9
    const VolumeInfo i = probe_volume(path);
    if (decoded_bytes(i, path) > (std::uint64_t{64} << 20)) return;  // chunks never written: fill values, no defect
    (void)prove_volume(path);
    const Volume v = read_volume(path);
    if (v.bytes.size() != static_cast<std::size_t>(v.grid.voxel_count()) * sample_size(v.type)) __builtin_trap();
    if (i.grid.dims != v.grid.dims) __builtin_trap();
#elif FUZZ_KIND == 2
    (void)probe_point_set(path);
    const PointSet s = read_point_set(path);
    (void)s;
#elif FUZZ_KIND == 3
    std::FILE* f = std::fopen(path.c_str(), "rb");
    if (!f) return;
    struct Closer {
        std::FILE* f;
        ~Closer() { std::fclose(f); }
    } closer{f};
    StreamReader r(f, path);
    r.read_meta();
    std::vector<char> out;
    while (r.next_data(out)) {
        if (out.size() > (std::size_t{64} << 20)) out.clear();
    }
#elif FUZZ_KIND == 4
    (void)BrickStore::open(path);
    (void)verify_brick_store(path, std::uint64_t{256} << 20);
#elif FUZZ_KIND == 5
    (void)SampleStore::open(path);
#elif FUZZ_KIND == 6
    // oracle: at least one position, every coordinate finite
    const std::vector<Vec3> p = read_positions(path);
    if (p.empty()) __builtin_trap();
    for (const Vec3& v : p)
        if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z)) __builtin_trap();
#elif FUZZ_KIND == 7
    // oracle: every record kept is finite, with a unit normal and a positive radius
    for (const PointRecord& r : read_oriented_points_vtp(path).points) {
        double len2 = 0;
        for (int a = 0; a < 3; ++a) {
            if (!std::isfinite(r.pos[a]) || !std::isfinite(r.normal[a])) __builtin_trap();
            len2 += double(r.normal[a]) * r.normal[a];
        }
        if (!(std::abs(len2 - 1) < 1e-4) || !(r.radius > 0) || !std::isfinite(r.radius) || !std::isfinite(r.value)) __builtin_trap();
    }
#endif
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    std::string_view all(reinterpret_cast<const char*>(data), size);
    const std::string second = FUZZ_SECOND;
    if (!second.empty()) {
        const std::size_t nul = all.find('\0');
        put(second, nul == std::string_view::npos ? std::string_view() : all.substr(nul + 1));
        all = all.substr(0, nul);
    }
    put(FUZZ_MAIN, all);
    try {
        run((dir() / FUZZ_READ).string());
    } catch (const FormatError&) {
    } catch (const IoError&) {
    } catch (const InvalidArgument&) {
    }
    return 0;
}
