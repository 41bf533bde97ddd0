// `mpirun -np N meshless batch ARCHIVE -o OUT ...`: the nightly job across the ranks of an MPI launch
// (docs/architecture.md "Distribution"). The volumes are dealt on request, largest first (the size
// order of stream/batch_shard.hpp): a rank asks rank 0 for its next volume when it has finished one
// (stream/unit_deal.hpp; rank 0 converts too), so a big scan starts first and a rank that drew small
// ones takes more of them. Each rank holds its shard's lock (K/N, stream/batch_lock.hpp) and rank 0
// sweeps the archive's stale temporaries before the first volume is dealt, so the outputs, sidecars
// and skipping are those of one process; then the ranks' results are gathered and rank 0 returns the
// whole archive's run (every volume in archive order, the longest rank's time), as one process would
// have. Other ranks return their own share. Rank 0's progress counts the share of the archive's
// bytes dealt.
// Throws what run_batch throws on this rank (the caller ends the job: a rank's failure to run at all
// is not a volume's failure, which is a result like any other).
// Thread-safety: one call per rank; collective (every rank must call it).
// Dissertation: none (the nightly conversion of archives around chapter 3's isosurfaces).
#pragma once
#include <exception>
#include <functional>
#include <string>

#include "stream/batch_job.hpp"
#include "stream/mpi_session.hpp"

namespace meshless {

/// on_deal_error: what rank 0's deal thread threw (the other ranks then wait for a volume: end the job).
BatchRun run_batch_ranks(const std::string& archive, BatchSettings s, const BatchCallbacks& cb, MpiSession& mpi,
                         std::function<void(std::exception_ptr)> on_deal_error);

}  // namespace meshless
