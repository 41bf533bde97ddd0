// MPI for `mpirun -np N meshless isosurface vol.mlb ...` (docs/architecture.md "Distribution"): the session
// (init/finalize, rank, size, reductions, abort) and MpiChannel, the RankChannel over which ranks
// stream their batches to rank 0 (stream/rank_merge.hpp), so the merged output is byte-identical to
// the single-process run and rank 0 never holds it. No MPI header is included here: a launch under
// mpirun is recognised from the launcher's environment (OMPI_COMM_WORLD_SIZE, PMI_SIZE); a plain
// run never initialises MPI, and never loads it: the MPI code lives in a plugin beside the
// executable (stream/mpi_backend.hpp, built from stream/mpi_plugin/ when CMake finds MPI), loaded by
// the MpiSession constructor (dlopen of the file beside /proc/self/exe).
// Failure: the front end that catches a rank's error prints it and calls abort(), which ends the whole
// job (MPI_Abort), so no rank presents partial output as complete (rank 0 writes through a temporary
// name + rename). Thread-safety: the plugin serialises its MPI calls (stream/mpi_backend.hpp).
#pragma once
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "stream/mpi_backend.hpp"
#include "stream/rank_merge.hpp"

namespace meshless {

/// World size the launcher announced (1 when not launched by mpirun).
int launched_world_size();
/// This process's rank as the launcher announced it (0 when not launched by mpirun).
int launched_world_rank();
/// The ranks the launcher started on this machine (the world size when it does not say; 1 when not
/// launched by mpirun): they share its memory.
int launched_local_size();
/// Whether this build can run under MPI.
bool mpi_built();

class MpiSession {
public:
    /// Loads the MPI plugin and runs MPI_Init; throws InvalidArgument (kernels/errors.hpp: the run
    /// asks for what this build cannot do) when the build has no MPI plugin or it cannot be loaded
    /// (the message names the file and dlerror()).
    MpiSession(int* argc, char*** argv);
    ~MpiSession();
    MpiSession(const MpiSession&) = delete;
    MpiSession& operator=(const MpiSession&) = delete;
    int rank() const { return rank_; }
    int size() const { return size_; }
    /// Element-wise sum over ranks, on rank 0. Collective.
    std::vector<std::int64_t> sum_to_root(const std::vector<std::int64_t>& v);
    /// Every rank's bytes concatenated in rank order, on every rank. Collective.
    std::vector<std::byte> allgather(std::span<const std::byte> mine);
    /// Ends every rank of the job with this exit code (does not return).
    [[noreturn]] void abort(int code);

    MpiBackend& backend() const { return *backend_; }
    /// Whether this rank has begun talking to the others (a collective, or a channel opened): before,
    /// an error every rank meets alike (the options') may end each rank on its own, without an abort.
    bool communicated() const { return communicated_; }
    void note_communication() const { communicated_ = true; }

private:
    mutable bool communicated_ = false;
    void* plugin_ = nullptr;  // dlopen handle
    std::unique_ptr<MpiBackend> backend_;
    int rank_ = 0, size_ = 1;
};

/// Byte messages to rank 0 in synchronous mode (MPI_Issend) with at most `window` unreceived
/// messages per sender: a sender blocks on its oldest message once the window is full, so neither
/// side buffers more than window messages whatever the output size. Receives probe for the size.
/// One channel per rank; the stream's calls (send_to_root, receive_from, flush) come from one thread,
/// the deal's (request_unit, poll_request, grant) may come from another (the plugin serialises MPI).
class MpiChannel final : public RankChannel {
public:
    explicit MpiChannel(const MpiSession& s, int window = 4);
    ~MpiChannel() override;
    void send_to_root(std::vector<std::byte> message) override;
    void receive_from(int rank, std::vector<std::byte>& message) override;
    void flush() override;
    std::optional<std::size_t> request_unit() override;
    std::optional<int> poll_request() override;
    void grant(int rank, std::optional<std::size_t> unit) override;

private:
    MpiBackend& backend_;
};

}  // namespace meshless
