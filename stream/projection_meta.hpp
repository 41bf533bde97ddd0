// What a Newton projection onto a meshless field records in a stream's metadata (dissertation
// sections 4.4 and 5.6): the projection, the field's name and the tolerance, and the picture frame
// widened for how far Newton may move a seed. Shared by the multiblock and scattered isosurfaces
// (stream/block_isosurface.hpp, stream/scattered_isosurface.hpp) and `meshless project`, so that the
// in-process command and `generate | project` record the same bytes. Throws nothing but std::bad_alloc.
#pragma once
#include <string>

#include "formats/point_stream.hpp"
#include "stream/field_project_stage.hpp"

namespace meshless {

/// The default --max-travel: a seed moves at most this many cell diagonals (section 4.4).
inline constexpr double kDefaultMaxTravel = 2;

/// Sets `projection newton`, `field` and `tolerance` (the seed tolerance, a fraction of the cell diagonal).
void add_projection_meta(StreamMeta& m, const std::string& field, const FieldProjectParams& p);

/// A seed stream whose frame (bounds_lo/hi) was widened for Newton moving its seeds up to
/// frame_travel cell diagonals of frame_cell_diagonal (the scattered seeds): widened further for a
/// larger max_travel (cell diagonals), so that the projected points stay inside it. An unlimited
/// travel (infinity), or metadata without those keys, leaves it.
void widen_frame_for_travel(StreamMeta& m, double max_travel);

}  // namespace meshless
