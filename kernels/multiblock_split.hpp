// A regular volume rewritten as the multiblock and AMR layouts of dissertation chapter 4 (Figure 4.3:
// overlapping, semi-conforming, non-conforming grids; section 4.5's test sets: bucky ball on two
// semi-conforming grids, neghip on two overlapping grids, fuel injection on five overlapping grids),
// plus rotated curvilinear blocks and a 3-level cell-centred AMR hierarchy, so that the isosurface
// from blocks can be compared against the original volume. Pure compute; `meshless split` writes
// the result (formats/vtm_writer.hpp, formats/vthb_writer.hpp).
//
// Notation: the volume has n_a nodes and C_a = n_a - 1 cells along axis a (spacing h_a, origin o_a);
// the split axis A is the longest axis in world units (the first of equal ones).
//   overlapping      K blocks (--blocks, default 2) along A, each the volume's own nodes over a node
//                    range; block b spans cells [t_b - floor(ov/2), t_{b+1} + ceil(ov/2)] clamped to
//                    [0, C_A], t_b = round(b C_A / K), so neighbours share exactly `ov` cell layers
//                    (ov + 1 node planes; ov = 0: conforming, one shared node plane). Values = the
//                    volume's samples, positions = its nodes.
//   semi-conforming  2 blocks meeting at the node plane m = 2 floor(C_A / 4) of axis A: block 0 = the
//                    volume's nodes 0..m along A (full resolution), block 1 = every other node
//                    (indices m, m+2, ... along A, 0, 2, ... along the others: half resolution), so on
//                    the shared face the nodes coincide only at every second node of block 0. Where C_a
//                    is odd, block 1 ends one cell short of the far face along a (its last even node).
//   non-conforming   2 blocks meeting at the plane m (as above): block 0 = the volume's nodes 0..m along
//                    A; block 1 = a lattice over [m h_A, C_A h_A] x the full extent of the other axes
//                    with spacing ~1.5x coarser (n' = round(C/1.5) + 1 nodes over C cells), values
//                    trilinear from the volume, so its nodes on the shared face do not coincide with
//                    block 0's (only the face corners and the domain edges do).
//   rotated          K blocks (default 2) over the overlapping layout's ranges, each a curvilinear
//                    lattice of n'_a = round(0.8 C_a) + 1 nodes spanning its box, twisted about the
//                    box's axis A through its centre by angle (+-twist degrees, alternating per block)
//                    * sin(pi u) sin(pi v) sin(pi w) (u, v, w in [0,1] across the box, so the faces
//                    stay flat), clamped to the box; values trilinear from the volume at the twisted
//                    positions. Blocks share no node of the volume's lattice or of each other (except
//                    by coincidence on the box faces).
//   amr              see split_amr below.
// Everything is positions in world units (the volume's origin/spacing) and values in its units.
// Throws InvalidArgument when the volume is too small for the layout (fewer than 3 nodes along an
// axis; semi/non-conforming need C_A >= 4; K > C_A / 2; ov >= C_A) or the parameters are out of
// range. Reentrant; allocates the blocks.
#pragma once
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "kernels/grid.hpp"
#include "kernels/structured_block.hpp"

namespace meshless {

enum class SplitLayout { overlapping, semi_conforming, non_conforming, rotated, amr };

/// "overlapping", "semi-conforming", "non-conforming", "rotated", "amr".
const char* to_string(SplitLayout l);
std::optional<SplitLayout> parse_split_layout(std::string_view s);

struct SplitParams {
    int blocks = 2;           ///< K for overlapping / rotated (>= 1)
    int overlap = 2;          ///< shared cell layers for overlapping / rotated (>= 0)
    double twist_deg = 15.0;  ///< rotated: largest twist angle in degrees (|twist| < 45)
};

/// Block values as doubles; positions world. `value_name` becomes Multiblock::value_name,
/// format "split".
Multiblock split_volume(const VolumeView& v, SplitLayout layout, const SplitParams& p = {},
                        const std::string& value_name = "scalars");

/// The volume trilinearly resampled to `n` nodes along its longest world axis and
/// max(1, round((n - 1) extent_a / extent_A)) + 1 along each other axis a, spanning the same world
/// box (node 0 and the last node of each axis stay at the volume's corners). float32 samples.
/// Throws InvalidArgument for n < 2 or n > 4096, or more than 2^30 samples in all.
Volume resample_volume(const VolumeView& v, std::int64_t n);

/// Trilinear value of the volume at a world position, clamped into the volume's box.
double sample_trilinear(const VolumeView& v, const Vec3& world);

// ---- AMR (vtkOverlappingAMR, cell-centred) -------------------------------------------------------
// A 3-level hierarchy, refinement ratio 2, cell data:
//   finest cells (level 2) = the volume's own cells (spacing h); the hierarchy covers the first
//   F_a = 4 floor(C_a / 4) cells of each axis (the last C_a mod 4 cell layers are dropped, so pick
//   n_a = 4k + 1 to keep everything); level 1 cells are 2h, level 0 cells 4h (the volume coarsened
//   by 4; level 0 covers the whole domain with one box).
//   Cell values: a level-2 cell = the mean of its 8 corner samples (= the trilinear interpolant at
//   the cell centre); a coarser cell = the mean of the level-2 cells it covers (the conservative
//   "average down" of AMR codes, = the mean of the trilinear interpolant over the cell).
//   Refinement: a level-l cell (l = 0, 1) is flagged when iso is given and the range of the level-2
//   values it covers (grown by one level-2 cell on every side) contains iso; without iso, level 1
//   covers the middle half of the domain along each axis ([F/4, 3F/4) in finest cells) and level 2 the
//   middle half of that. Flagged cells are grown by one cell on each side, the level is tiled into
//   tiles of `tile` x tile x tile cells (clamped to the domain) and each tile holding a flagged cell
//   becomes one box of the next level, so level 2 boxes lie inside level 1 boxes (proper nesting:
//   a level-2 box is a refined tile of level-1 cells that lie in level-1 boxes).
struct AmrBox {
    int level = 0;
    std::array<std::int64_t, 3> lo{0, 0, 0}, hi{0, 0, 0};  ///< cell index box, inclusive, in its level's index space
    std::vector<double> value;                              ///< (hi-lo+1) product cell values, i fastest
    std::array<std::int64_t, 3> cells() const { return {hi[0] - lo[0] + 1, hi[1] - lo[1] + 1, hi[2] - lo[2] + 1}; }
};

struct AmrHierarchy {
    std::array<double, 3> origin{0, 0, 0};   ///< world corner of cell (0,0,0) at every level
    std::array<double, 3> spacing0{1, 1, 1}; ///< level-0 cell size; level l: spacing0 / 2^l
    int levels = 3;
    int refinement = 2;
    std::vector<AmrBox> boxes;               ///< ordered by level, then by tile (z, y, x)
    std::string value_name = "scalars";
    std::array<double, 3> spacing(int level) const {
        const double f = static_cast<double>(1 << level);
        return {spacing0[0] / f, spacing0[1] / f, spacing0[2] / f};
    }
};

struct AmrParams {
    std::optional<double> iso;  ///< refine where the values cross iso; nullopt: middle halves
    int tile = 8;               ///< box edge in cells of the level being refined (>= 2)
};

/// Throws InvalidArgument when some C_a < 4 (no level-0 cell) or tile < 2.
AmrHierarchy split_amr(const VolumeView& v, const AmrParams& p = {}, const std::string& value_name = "scalars");

/// The hierarchy as cell-centred blocks (StructuredBlock::cell_centred, nodes at the cell centres,
/// level set), the way the block readers present AMR data. format "vthb".
Multiblock amr_to_multiblock(const AmrHierarchy& h);

}  // namespace meshless
