// What a batch carries, as the stage graph declares it (docs/architecture.md "Core types", "Typed
// graphs"): every Source says what it gives, every Stage what it takes and what it gives for each, every
// Sink what it takes, and run_pipeline (stream/runner.hpp) checks the chain once, when the graph is
// built, before the first batch is pulled. A batch's record arrays are the payload's own types
// (kernels/records.hpp: SampleRecord, PointRecord, SeedRecord; Mesh; FieldQueries).
#pragma once
#include <cstdint>
#include <initializer_list>
#include <string>

#include "kernels/records.hpp"

namespace meshless {

enum class Payload : std::uint8_t {
    cells,    ///< work: cell rows of a grid, a brick or a slab chunk (Batch::cells, brick, chunk); no records yet
    samples,  ///< Batch::samples: isosurface samples before projection (section 3.2)
    points,   ///< Batch::points (and point_block): projected surface points, the splats
    seeds,    ///< Batch::seeds: multiblock/AMR and scattered-data seeds before projection (sections 4.4, 5.3)
    mesh,     ///< Batch::mesh and mesh_seam: marching-cubes pieces
    queries,  ///< Batch::query: field query positions, then their values
};

/// A set of payloads (what a stage or a sink takes).
class PayloadSet {
public:
    constexpr PayloadSet() = default;
    constexpr PayloadSet(Payload p) : bits_(bit(p)) {}  // NOLINT: one payload is a set of one
    constexpr PayloadSet(std::initializer_list<Payload> ps) {
        for (Payload p : ps) bits_ |= bit(p);
    }
    /// Every payload: a stage that passes any batch through (progress), a sink that only counts.
    static constexpr PayloadSet any() {
        PayloadSet s;
        s.bits_ = 0x3f;
        return s;
    }
    constexpr bool has(Payload p) const { return (bits_ & bit(p)) != 0; }
    constexpr bool empty() const { return bits_ == 0; }
    constexpr bool operator==(const PayloadSet&) const = default;
    /// What both sets take (a tee's two sinks).
    constexpr PayloadSet operator&(PayloadSet o) const {
        PayloadSet s;
        s.bits_ = static_cast<std::uint8_t>(bits_ & o.bits_);
        return s;
    }

private:
    static constexpr std::uint8_t bit(Payload p) { return static_cast<std::uint8_t>(1u << static_cast<unsigned>(p)); }
    std::uint8_t bits_ = 0;
};

/// "cell rows", "samples", "points", "seeds", "mesh pieces", "field queries".
const char* payload_name(Payload p);
/// The names of a set joined by " or ", "nothing" when empty.
std::string payload_names(PayloadSet s);
/// The record kind a batch of this payload is tagged with (Batch::kind). Cell-row work carries no
/// records, whatever its tag (the stage that fills it sets the kind); sample is returned for it.
RecordKind record_kind_of(Payload p);
/// The payload of a stream's record kind (formats/point_stream.hpp).
Payload payload_of(RecordKind k);

}  // namespace meshless
