// `mpirun -np N meshless batch ARCHIVE -o OUT ...`: the nightly job across the ranks of an MPI launch
// (docs/architecture.md "Distribution"). Each rank converts the volumes `--shard K/N` would give
// shard K = its rank (stream/batch_shard.hpp: by size, largest first, dealt round-robin), with the
// shards' locks (stream/batch_lock.hpp), so the outputs, sidecars and skipping are those of one
// process; then the ranks' results are gathered and rank 0 returns the whole archive's run (every
// volume in archive order, the longest rank's time), as one process would have. Other ranks return
// their own share.
// Throws what run_batch throws on this rank (the caller ends the job: a rank's failure to run at all
// is not a volume's failure, which is a result like any other).
// Thread-safety: one call per rank; collective (every rank must call it).
// Dissertation: none (the nightly conversion of archives around chapter 3's isosurfaces).
#pragma once
#include <string>

#include "stream/batch_job.hpp"
#include "stream/mpi_session.hpp"

namespace meshless {

BatchRun run_batch_ranks(const std::string& archive, BatchSettings s, const BatchCallbacks& cb, MpiSession& mpi);

}  // namespace meshless
