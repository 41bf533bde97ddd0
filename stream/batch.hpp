// Batch: the unit of in-flight memory in the stage graph (docs/architecture.md "Core types").
//
// A batch holds records of one kind (samples or points), at most kMaxBatchRecords, and a sequence
// number assigned by the source; sinks receive batches in sequence order whatever the thread count,
// so outputs are byte-identical across --threads. A batch may also be empty (a source's unit of work
// that produced nothing) and is still delivered, to keep sequence numbers dense.
#pragma once
#include <cstdint>
#include <memory>
#include <vector>

#include "kernels/grid.hpp"
#include "kernels/marching_cubes.hpp"
#include "kernels/vec3.hpp"
#include "kernels/records.hpp"

namespace meshless {

inline constexpr std::size_t kMaxBatchRecords = 65536;

/// A unit of work for a generating stage: the cell rows [k0, k1) of a regular grid
/// (row r = j + (ny-1)*k, see kernels/cell_sampling.hpp).
struct CellRange {
    std::int64_t k0 = 0, k1 = 0;
};

/// Consecutive z-slices [z0, z0 + samples.grid.dims[2]) of a volume streamed slab by slab
/// (stream/slab_source.hpp): `samples.grid` is the volume's grid with dims[2] = the slice count and
/// the volume's origin, so positions are computed with index offset z0, bit for bit as in memory.
struct VolumeChunk {
    Volume samples;
    std::int64_t z0 = 0;
};

/// Field queries (probe / slice / resample): world positions and, once a FieldEvaluateStage ran,
/// the field's value (and gradient when want_grad) at each.
struct FieldQueries {
    std::vector<Vec3> at;
    std::vector<double> value;
    std::vector<Vec3> grad;  ///< empty unless want_grad
    bool want_grad = false;
};

struct Batch {
    std::uint64_t seq = 0;
    RecordKind kind = RecordKind::sample;
    CellRange cells;                    ///< work description (generate stage input), else empty
    std::int64_t brick = -1;            ///< brick-store work: index of the brick the cell rows are in
    std::shared_ptr<const VolumeChunk> chunk;  ///< slab-streamed work: the slices the cell rows (local to it) are in
    std::vector<SampleRecord> samples;  ///< valid when kind == sample
    std::vector<PointRecord> points;    ///< valid when kind == point
    std::vector<std::uint32_t> point_block;  ///< kind == point: empty, or per point the id of the block
                                             ///< it was seeded in (multiblock/AMR path, PLY `block`)
    std::vector<SeedRecord> seeds;      ///< valid when kind == seed
    Mesh mesh;                          ///< valid when kind == mesh: a marching-cubes piece (local indices)
    std::vector<std::uint64_t> mesh_seam;  ///< kind == mesh: per vertex, its edge key if on the piece's
                                           ///< boundary (shared with a neighbour), else kNoSeam
    FieldQueries query;                 ///< valid when kind == query
    std::uint64_t count() const {
        switch (kind) {
            case RecordKind::sample: return samples.size();
            case RecordKind::mesh: return mesh.triangle_count();
            case RecordKind::query: return query.at.size();
            case RecordKind::seed: return seeds.size();
            case RecordKind::point: break;
        }
        return points.size();
    }
    static constexpr std::uint64_t kNoSeam = ~std::uint64_t{0};
};

}  // namespace meshless
