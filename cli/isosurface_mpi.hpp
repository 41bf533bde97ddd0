// `mpirun -np N meshless isosurface vol.mlb ...`: the active bricks (Morton order) are dealt
// round-robin to the ranks; every rank iso-splats its bricks through the stage graph and streams the
// point batches to rank 0 (stream/isosplat_ranks.hpp over cli/mpi_session.hpp's MpiChannel), which
// writes them, in the single-process order, through the same outputs as the single-process command
// (the `write` callback). Rank 0's memory holds the batches in flight, never the output.
// Failure: a rank that fails prints its error and aborts the job (MPI_Abort), every rank exits
// non-zero, and no output is renamed into place.
#pragma once
#include <functional>
#include <string>

#include "cli/args.hpp"
#include "formats/point_stream.hpp"
#include "stream/isosplat_pipeline.hpp"

namespace meshless::cli {

/// Runs the graph into the command's outputs: builds the sink(s) for `meta`, calls produce(sink)
/// (which runs the graph and calls sink.finish()), completes the outputs, returns the points written.
using IsosurfaceWriter = std::function<std::size_t(const StreamMeta& meta, const std::function<void(Sink&)>& produce)>;

struct MpiIsosurfaceResult {
    bool root = false;       ///< this process is rank 0 (it wrote the outputs)
    int ranks = 1;
    std::string path;        ///< the input
    IsoSplatResult result;   ///< statistics summed over ranks (rank 0 only); seconds = rank 0's
    std::size_t points = 0;  ///< points written (rank 0 only)
};

MpiIsosurfaceResult isosurface_mpi(const Args& a, int argc, char** argv, double iso, Projection mode,
                                   const SamplingParams& sp, int nthreads, const IsosurfaceWriter& write);

}  // namespace meshless::cli
