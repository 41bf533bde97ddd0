// Records that flow between stages, byte-identical in memory and on a pipe (little endian, x86).
//
// PointRecord (32 bytes): a projected, oriented surface sample, ready to splat or write.
// SampleRecord (88 bytes): an unprojected sample of paradigm (C) (dissertation section 3.4): the
//   sample position, the trilinear value and gradient there, the splat radius, and the cell it came
//   from (lower corner, edge lengths, eight corner values) so that both the approximate (Eq. 3.5)
//   and the exact (Eq. 3.3) projection can run downstream without the volume.
#pragma once
#include <cmath>
#include <cstdint>
#include <type_traits>

namespace meshless {

struct PointRecord {
    float pos[3];     ///< world position
    float normal[3];  ///< unit normal -grad f / |grad f|, pointing to decreasing values (VTK's convention)
    float radius;     ///< splat radius, world units
    float value;      ///< field value at pos (== iso when projected exactly)
};
static_assert(sizeof(PointRecord) == 32 && std::is_trivially_copyable_v<PointRecord>);

/// True when an oriented point can be drawn: finite position, normal, radius and value, a radius
/// > 0 and a normal of non-zero finite length. The oriented-point readers splat draws from (PLY,
/// VTP) drop the others and count them.
inline bool drawable(const PointRecord& p) {
    double len2 = 0;
    bool ok = std::isfinite(p.radius) && p.radius > 0 && std::isfinite(p.value);
    for (int a = 0; a < 3; ++a) {
        ok = ok && std::isfinite(p.pos[a]) && std::isfinite(p.normal[a]);
        len2 += static_cast<double>(p.normal[a]) * p.normal[a];
    }
    return ok && len2 > 0 && std::isfinite(len2);
}

struct SampleRecord {
    float pos[3];        ///< sample position (cell centre in paradigm C), world units
    float grad[3];       ///< gradient of the trilinear interpolant at pos, value units / world unit
    float value;         ///< trilinear value at pos
    float radius;        ///< splat radius, world units
    float cell_lo[3];    ///< world position of the cell's corner (i,j,k)
    float cell_size[3];  ///< cell edge lengths s_x, s_y, s_z (world units)
    float corner[8];     ///< corner values, index = dx + 2*dy + 4*dz
};
static_assert(sizeof(SampleRecord) == 88 && std::is_trivially_copyable_v<SampleRecord>);

/// SeedRecord (40 bytes): a seed of the multiblock/AMR path (dissertation sections 4.4-4.5): one
///   barycentric-lattice sample inside a marching-cubes triangle of a block cell, before the Newton
///   projection onto the continuous field. base_radius = sqrt(2A / (pi n (n+1))) for the triangle's
///   area A and the lattice parameter n; the projected point's radius is 2 (1 + d/l) base_radius
///   (d the distance travelled, l = cell_diagonal).
struct SeedRecord {
    float pos[3];         ///< seed position, world units
    float normal[3];      ///< the triangle's unit normal, pointing to decreasing values (VTK's convention)
    float value;          ///< the block interpolant's value at pos (== iso up to rounding)
    float base_radius;    ///< sqrt(2A / (pi n (n+1))), world units
    float cell_diagonal;  ///< diagonal of the seeding cell (l of section 4.4), world units
    std::uint32_t block;  ///< index of the block the seed came from
};
static_assert(sizeof(SeedRecord) == 40 && std::is_trivially_copyable_v<SeedRecord>);

/// mesh: a marching-cubes piece, query: field query positions and results, in a stage-graph batch
/// (stream/batch.hpp); never on a pipe.
enum class RecordKind : std::uint32_t { point = 1, sample = 2, mesh = 3, query = 4, seed = 5 };

}  // namespace meshless
