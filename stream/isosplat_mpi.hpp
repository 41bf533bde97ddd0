// Paradigm (C) iso-splatting of a brick store under mpirun (dissertation section 3.6; docs/architecture.md
// "Distribution"), the recipe of `mpirun -np N meshless isosurface vol.mlb ...` (and any other front end):
// the active bricks (Morton order) are dealt round-robin to the ranks; every rank iso-splats its bricks
// through the stage graph and streams the point batches to rank 0 (stream/isosplat_ranks.hpp over
// stream/mpi_session.hpp's MpiChannel), which writes them, in the single-process order, through the
// outputs the `write` callback builds. Rank 0's memory holds the batches in flight, never the output.
// Units: isovalue in the volume's sample units; seconds of wall time (rank 0's).
// Throws InvalidArgument when the input is not a brick store (.mlb), and what the stages, the channel
// and the sinks throw. A front end catching an error on any rank should end the job with
// MpiSession::abort, so that every rank exits non-zero and no output is renamed into place.
#pragma once
#include <cstddef>
#include <functional>
#include <string>

#include "formats/point_stream.hpp"
#include "stream/isosplat_pipeline.hpp"

namespace meshless {

class MpiSession;
struct VolumeInput;

/// Runs the graph into the front end's outputs: builds the sink(s) for `meta`, calls produce(sink)
/// (which runs the graph and calls sink.finish()), completes the outputs, returns the points written.
using IsosurfaceWriter = std::function<std::size_t(const StreamMeta& meta, const std::function<void(Sink&)>& produce)>;

struct MpiIsosurfaceResult {
    bool root = false;       ///< this process is rank 0 (it wrote the outputs)
    int ranks = 1;
    std::string path;        ///< the input
    IsoSplatResult result;   ///< statistics summed over ranks (rank 0 only); seconds = rank 0's
    std::size_t points = 0;  ///< points written (rank 0 only)
};

/// This rank's share of the run over `in` (a brick store); `write` is called on rank 0 only, with the
/// stream metadata of the volume at `iso` (producer = `command_line`, projection = `mode`). Collective:
/// every rank of `mpi` calls it. `nthreads` threads per rank.
MpiIsosurfaceResult run_isosplat_mpi(MpiSession& mpi, VolumeInput& in, double iso, Projection mode, const SamplingParams& sp,
                                     int nthreads, const std::string& command_line, const IsosurfaceWriter& write);

}  // namespace meshless
