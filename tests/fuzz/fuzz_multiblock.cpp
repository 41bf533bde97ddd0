// libFuzzer target for the structured multiblock and AMR readers (formats/multiblock_reader.hpp:
// formats/vtk_multiblock, formats/vtk_structured, formats/plot3d's structured read).
//
// Built only with Clang and -DMESHLESS_BUILD_FUZZ=ON (see fuzz_ply.cpp):
//   cmake -S . -B build-fuzz -G Ninja -DCMAKE_CXX_COMPILER=clang++ -DMESHLESS_BUILD_FUZZ=ON \
//         -DMESHLESS_BUILD_TESTS=OFF -DCMAKE_BUILD_TYPE=RelWithDebInfo
//   cmake --build build-fuzz --target fuzz_multiblock
//   scripts/fuzz_multiblock_seeds.sh corpus-mb      # a few seeds from ../shared/data
//   build-fuzz/tests/fuzz/fuzz_multiblock corpus-mb -max_total_time=60 -rss_limit_mb=1024
// An input is "MODE COLLECTION \0 PIECE": MODE (the first byte, mod 4) picks what COLLECTION is
// written as: 0 x.vthb, 1 x.vtm, 2 x.vts (read directly), 3 a PLOT3D pair (COLLECTION -> gxyz.bin,
// PIECE -> gq.bin, its sibling q file); PIECE is written as p.vti, p.vts and p.vtr, so a collection
// naming any of them finds it. Files live in one temporary directory per process, rewritten per
// input. The only acceptable failures are FormatError and IoError (one line each); anything else
// (a crash, a sanitizer report, another exception, an allocation the data does not justify, a
// hang) is a defect. Oracle: every block's arrays have node_count() entries.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>

#include "formats/multiblock_reader.hpp"
#include "kernels/errors.hpp"

using namespace meshless;

namespace {

const std::filesystem::path& dir() {
    static const std::filesystem::path d = [] {
        auto p = std::filesystem::temp_directory_path() / ("meshless-fuzz-mb-" + std::to_string(::getpid()));
        std::filesystem::create_directories(p);
        return p;
    }();
    return d;
}

void put(const std::string& name, std::string_view bytes) {
    std::ofstream f(dir() / name, std::ios::binary | std::ios::trunc);
    f.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size < 1) return 0;
    const int mode = data[0] % 4;
    const std::string_view all(reinterpret_cast<const char*>(data) + 1, size - 1);
    const std::size_t nul = all.find('\0');
    const std::string_view head = all.substr(0, nul);
    const std::string_view piece = nul == std::string_view::npos ? std::string_view() : all.substr(nul + 1);
    static const char* names[4] = {"x.vthb", "x.vtm", "x.vts", "gxyz.bin"};
    for (const char* p : {"p.vti", "p.vts", "p.vtr"}) put(p, piece);
    if (mode == 3) put("gq.bin", piece);
    put(names[mode], head);
    try {
        PointSetOptions o;
        o.strict = (size % 2) == 0;
        MultiblockDetails det;
        const Multiblock mb = read_multiblock({(dir() / names[mode]).string()}, o, det);
        for (const auto& b : mb.blocks) {
            const auto n = static_cast<std::size_t>(b.node_count());
            if (b.node.size() != n || b.value.size() != n || (!b.valid.empty() && b.valid.size() != n)) std::abort();
        }
    } catch (const FormatError& e) {
        if (std::string_view(e.what()).find('\n') != std::string_view::npos) std::abort();
    } catch (const IoError&) {
    }
    return 0;
}
