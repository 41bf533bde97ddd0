// The multiblock/AMR isosurface as one job of a front end (dissertation chapter 4, sections
// 4.3-4.6): blocks read and planned (stream/block_isosurface.hpp) and their field fitted, run into
// the outputs of an IsosurfaceJob (stream/isosurface_job.hpp: a PLY/VTP with the `block` property
// and/or a PNG), with the progress of the cells handed out and the --stats block. What
// `meshless isosurface BLOCKS...` runs once its options are checked (and any other front end).
// Throws what stream/block_isosurface.hpp and stream/point_outputs.hpp throw.
#pragma once
#include <cstdio>
#include <string>

#include "stream/block_isosurface.hpp"
#include "stream/isosurface_job.hpp"

namespace meshless {

/// The warnings (to `out`) of blocks in which no cell is crossed at `iso`: the isovalue outside
/// the valid nodes' values, or inside them but crossing no cell with valid corners.
void warn_if_no_block_cell_crossed(std::FILE* out, const BlockIsosurfaceInput& in, double iso);

/// Runs the isosurface of `in` onto the field `f` (fit_block_field) into j's outputs; the
/// statistics (j.stats) name `cmd`. Returns the points written.
std::size_t run_block_isosurface_job(const IsosurfaceJob& j, const BlockIsosurfaceInput& in, const IsosurfaceField& f,
                                     const char* cmd);

}  // namespace meshless
