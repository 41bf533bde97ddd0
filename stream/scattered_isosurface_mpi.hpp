// The scattered-data isosurface under mpirun (dissertation sections 5.4-5.7; docs/architecture.md
// "Distribution"), the recipe of `mpirun -np N meshless isosurface POINTS ...` (and any other front end):
// the stencil rows are dealt to the ranks on request (stream/stencil_ranks.hpp over
// stream/mpi_session.hpp's MpiChannel), rank 0 writes every rank's points, in the single-process order,
// through the outputs the `write` callback builds; the statistics are summed to rank 0. The mpu
// field's local fits are shared out the same way (mpi_fit_share), so every rank ends with the whole
// field. Units: isovalue in the points' value units; dedup a fraction of the point radius.
// Throws what the stages, the channel and the sinks throw; rank 0's deal service hands its error to
// on_deal_error (a front end ends the job there: the other ranks would wait for rows). A front end
// catching an error on any rank should end the job with MpiSession::abort.
#pragma once
#include <cstddef>
#include <exception>
#include <functional>

#include "kernels/field_params.hpp"
#include "stream/scattered_isosurface.hpp"

namespace meshless {

class MpiSession;

/// The FitShare (kernels/field_params.hpp) of the session's ranks: allgather over MPI.
FitShare mpi_fit_share(MpiSession& mpi);

struct ScatteredMpiResult {
    StencilRankResult totals;  ///< every rank's statistics summed (rank 0 only)
    std::size_t points = 0;    ///< points written (rank 0 only)
};

/// Runs the front end's outputs (rank 0): builds the sink(s), calls produce(sink) (which runs the graph
/// and calls sink.finish()), completes the outputs, returns the points written.
using ScatteredWriter = std::function<std::size_t(const std::function<void(Sink&)>& produce)>;

/// This rank's share of run_scattered_isosurface over `in` with `field` (null: the isovalue crosses no
/// data, an empty output and no channel); `write` is called on rank 0 only. Collective: every rank of
/// `mpi` calls it. `nthreads` threads per rank.
ScatteredMpiResult run_scattered_isosurface_mpi(MpiSession& mpi, const ScatteredIsosurfaceInput& in, const Field* field, double iso,
                                                int n, const FieldProjectParams& np, double dedup, int nthreads,
                                                const ScatteredWriter& write,
                                                const std::function<void(std::exception_ptr)>& on_deal_error);

}  // namespace meshless
