// Structured blocks of a multiblock grid or an AMR hierarchy, with their connectivity kept
// (dissertation chapter 4, sections 4.3-4.6): what the block readers produce (formats/
// multiblock_reader.hpp), what the marching-cubes seed stage walks cell by cell, and what the
// continuous meshless field is built from (to_point_set: every valid node, connectivity dropped).
//
// A block is a lattice of nodes, i fastest: node(i,j,k) = node[i + dims[0]*(j + dims[1]*k)], with a
// world position (curvilinear or not) and one scalar. A node with valid[n] == 0 (PLOT3D IBLANK 0, a
// NaN/Inf coordinate or value) is neither data for the field nor a cell corner: every hexahedral
// cell with such a corner is skipped. Cell-centred data (AMR boxes, VTK CellData) is stored with its
// cell centres as the nodes (cell_centred = true, dims = the box's cell counts), so the seed stage
// contours the lattice of centres and the field sees points at cell centres.
// Units: positions in the file's world units, values in the file's units.
// Thread-safety: plain data.
#pragma once
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "kernels/point_set.hpp"
#include "kernels/vec3.hpp"

namespace meshless {

struct StructuredBlock {
    std::string name;                            ///< e.g. "grid 1", "multicomb_0.vts", "level 2 box 5"
    std::array<std::int64_t, 3> dims{0, 0, 0};   ///< nodes along i, j, k (each >= 1)
    std::vector<Vec3> node;                      ///< dims[0]*dims[1]*dims[2] world positions, i fastest
    std::vector<double> value;                   ///< one scalar per node
    std::vector<std::uint8_t> valid;             ///< empty: every node valid; else 0 = blanked/NaN
    /// AMR: empty, or 1 where a finer level covers the node (kernels/amr_cover.hpp): a covered node
    /// is not data for the field (the finest data wins) and a cell whose corners are all covered is
    /// not seeded; the naive per-block marching cubes ignores it.
    std::vector<std::uint8_t> covered;
    int level = 0;                               ///< AMR level (0 = coarsest); 0 for plain multiblock
    bool cell_centred = false;                   ///< nodes are cell centres (AMR / CellData)

    std::int64_t node_count() const { return dims[0] * dims[1] * dims[2]; }
    std::int64_t index(std::int64_t i, std::int64_t j, std::int64_t k) const { return i + dims[0] * (j + dims[1] * k); }
    bool is_valid(std::int64_t n) const { return valid.empty() || valid[static_cast<std::size_t>(n)] != 0; }
    bool is_covered(std::int64_t n) const { return !covered.empty() && covered[static_cast<std::size_t>(n)] != 0; }
};

struct Multiblock {
    std::vector<StructuredBlock> blocks;
    std::string value_name;          ///< the scalar's name ("density", "phi", ...)
    std::string format;              ///< "plot3d", "vts", "vtm", "vthb", "vtm-amr", "volume"
    std::uint64_t blanked = 0;       ///< nodes marked invalid because of IBLANK == 0
    std::uint64_t nonfinite = 0;     ///< nodes marked invalid because of a NaN/Inf coordinate or value
    std::uint64_t covered = 0;       ///< valid AMR nodes covered by a finer level (not field data)
    std::vector<std::string> notes;  ///< reader notes (files paired, bytes ignored, ...)
};

/// Every valid, uncovered node of every block as one point set, one PointSetBlock per block (dims kept, count
/// = valid nodes), so that fields built from it carry the block structure in their messages.
/// dropped_blanked / dropped_nonfinite are copied from the multiblock.
PointSet to_point_set(const Multiblock& mb);

}  // namespace meshless
