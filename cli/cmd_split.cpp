// meshless split: a regular volume rewritten as the multiblock and AMR layouts of dissertation
// chapter 4 (Figure 4.3; section 4.5's test sets): options parsed here, the split and its files by
// stream/volume_split.hpp. kernels/multiblock_split.hpp has the exact definitions of the layouts.
// --resample N first resamples the volume trilinearly to N nodes along its longest axis (the
// dissertation's sets: bucky --resample 33 semi-conforming = 21,114 nodes as in Table 4.1).
#include <cstdio>
#include <filesystem>

#include "cli/commands.hpp"
#include "cli/common.hpp"
#include "cli/errors.hpp"
#include "stream/volume_split.hpp"

namespace meshless::cli {

int cmd_split(int argc, char** argv) {
    Args a("split", "VOLUME --layout overlapping|semi-conforming|non-conforming|rotated|amr [--blocks K] "
                    "[--overlap CELLS] [--resample N] [--iso V] -o PREFIX.vtm|PREFIX.vthb",
           "Writes a regular volume as multiblock pieces (the test sets of dissertation section 4.5, Figure 4.3),\n"
           "so isosurfaces from blocks can be compared with the volume. The split axis is the longest one.\n"
           "  overlapping      K blocks of the volume's own nodes, neighbours sharing --overlap cell layers\n"
           "  semi-conforming  2 blocks meeting at a plane, the second at half resolution (every other node):\n"
           "                   on the shared face the nodes coincide at every second node only\n"
           "  non-conforming   2 blocks meeting at a plane, the second a 1.5x coarser lattice sampled\n"
           "                   trilinearly: no coinciding nodes on the shared face\n"
           "  rotated          K curvilinear blocks (0.8x lattices twisted about the split axis by up to\n"
           "                   +-15 degrees, faces kept flat), values trilinear: no shared nodes\n"
           "  amr              3 levels, refinement 2, cell-centred: level 0 = the volume coarsened by 4,\n"
           "                   levels 1 and 2 (the volume's own cells) in boxes where the values cross --iso\n"
           "                   (else the middle half, then its middle half). A cell's value is the mean of\n"
           "                   the volume's cells it covers (a volume cell: the mean of its 8 corners).\n"
           "                   Axes of 4k+1 nodes keep every cell; otherwise the last (n-1) mod 4 cell\n"
           "                   layers are dropped.\n"
           "Writes PREFIX.vtm + PREFIX/PREFIX_<b>.vts (VTK XML StructuredGrid), or for amr\n"
           "PREFIX.vthb + PREFIX/PREFIX_<n>.vti (ImageData, CellData); ParaView opens both.");
    a.option("layout", "", "L", "overlapping | semi-conforming | non-conforming | rotated | amr (required)")
        .option("blocks", "", "K", "overlapping/rotated: number of blocks, 1..1024", "2")
        .option("overlap", "", "CELLS", "overlapping/rotated: cell layers shared by neighbouring blocks, 0..1048576", "2")
        .option("resample", "", "N", "first resample the volume trilinearly to N nodes along its longest axis, 3..4096")
        .option("iso", "", "V", "amr: refine where the values cross V (default: the middle halves)")
        .option("tile", "", "CELLS", "amr: box edge in cells of the level being refined, 2..4096", "8")
        .option("name", "", "NAME", "name of the scalar array in the pieces", "scalars")
        .option("output", "o", "PREFIX.vtm", "output index: .vtm (or .vthb for amr); pieces go to PREFIX/ (required)");
    add_volume_options(a);
    add_crop_option(a);
    a.positionals(1, 1);
    a.epilog("examples (the dissertation's multiblock sets, section 4.5 / Table 4.1):\n"
             "  meshless split ../shared/data/bucky/Bucky_32x32x32_uint8.raw --layout semi-conforming --resample 33 -o bucky.vtm\n"
             "  meshless split ../shared/data/neghip/neghip_64x64x64_uint8.raw --layout overlapping -o neghip.vtm\n"
             "  meshless split ../shared/data/fuel/fuel_64x64x64_uint8.raw --layout overlapping --blocks 5 -o fuel.vtm\n"
             "  meshless split VOLUME --layout amr --iso 128 -o hierarchy.vthb\n");
    if (!a.parse(argc, argv, 2)) return 0;
    const auto layout = parse_split_layout(a.require("layout"));
    if (!layout)
        throw UsageError("--layout: expected overlapping, semi-conforming, non-conforming, rotated or amr, got '" +
                         a.require("layout") + "'");
    const std::string out = a.require("output");
    const std::string ext = std::filesystem::path(out).extension().string();
    const std::string want = *layout == SplitLayout::amr ? ".vthb" : ".vtm";
    if (ext != want)
        throw UsageError("-o: the " + std::string(to_string(*layout)) + " layout writes a " + want + " file, got '" + out + "'");
    VolumeSplitOptions so;
    so.layout = *layout;
    const long long k = a.get_int_or("blocks", 2), ov = a.get_int_or("overlap", 2);
    if (k < 1 || k > 1024) throw UsageError("--blocks: expected 1..1024");
    if (ov < 0 || ov > 1 << 20) throw UsageError("--overlap: expected a number of cells >= 0");
    if ((a.has("blocks") || a.has("overlap")) && *layout != SplitLayout::overlapping && *layout != SplitLayout::rotated)
        throw UsageError("--blocks and --overlap apply to the overlapping and rotated layouts only");
    if ((a.has("iso") || a.has("tile")) && *layout != SplitLayout::amr)
        throw UsageError("--iso and --tile apply to the amr layout only");
    so.split.blocks = static_cast<int>(k);
    so.split.overlap = static_cast<int>(ov);
    so.name = a.get_or("name", "scalars");
    Volume v = load_volume(a);
    if (a.has("resample")) {
        const long long n = a.get_int_or("resample", 0);
        if (n < 3 || n > 4096) throw UsageError("--resample: expected 3..4096 nodes");
        v = resample_volume(v.view(), n);
    }
    const auto& g = v.grid;
    std::printf("split: %s (%lldx%lldx%lld), layout %s\n", terminal_safe(a.positional()[0]).c_str(), static_cast<long long>(g.dims[0]),
                static_cast<long long>(g.dims[1]), static_cast<long long>(g.dims[2]), to_string(*layout));
    if (*layout == SplitLayout::amr) {
        if (a.has("iso")) so.amr.iso = parse_finite(a.require("iso"), "--iso");
        const long long t = a.get_int_or("tile", 8);
        if (t < 2 || t > 4096) throw UsageError("--tile: expected 2..4096 cells");
        so.amr.tile = static_cast<int>(t);
    }
    write_volume_split(v, so, out, stdout);
    return 0;
}

}  // namespace meshless::cli
