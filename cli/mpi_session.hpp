// MPI for `mpirun -np N meshless isosurface vol.mlb ...` (DESIGN.md "Distribution"): ranks take
// disjoint, contiguous Morton ranges of the active bricks; rank 0 gathers the points in rank order,
// so the merged output is byte-identical to the single-process run. The MPI headers stay inside
// cli/mpi_session.cpp (built when CMake finds MPI; otherwise cli/mpi_session_none.cpp reports that
// this build has no MPI). A launch under mpirun is recognised from the launcher's environment
// (OMPI_COMM_WORLD_SIZE, PMI_SIZE, PMIX_RANK); a plain run never initialises MPI.
// Failure: a rank that fails prints its error and aborts the whole job (MPI_Abort), so no rank
// presents partial output as complete (rank 0 writes through a temporary name + rename).
#pragma once
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

namespace meshless::cli {

/// World size the launcher announced (1 when not launched by mpirun).
int launched_world_size();
/// Whether this build can run under MPI.
bool mpi_built();

class MpiSession {
public:
    /// MPI_Init; throws UsageError when the build has no MPI.
    MpiSession(int* argc, char*** argv);
    ~MpiSession();
    MpiSession(const MpiSession&) = delete;
    MpiSession& operator=(const MpiSession&) = delete;
    int rank() const { return rank_; }
    int size() const { return size_; }
    /// Concatenation of every rank's bytes in rank order, on rank 0 (empty elsewhere). Collective.
    std::vector<std::byte> gather_to_root(const void* data, std::size_t bytes);
    /// Element-wise sum over ranks, on rank 0. Collective.
    std::vector<std::int64_t> sum_to_root(const std::vector<std::int64_t>& v);
    /// Ends every rank of the job with this exit code (does not return).
    [[noreturn]] void abort(int code);

private:
    int rank_ = 0, size_ = 1;
};

}  // namespace meshless::cli
