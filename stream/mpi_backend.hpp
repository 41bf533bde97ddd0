// The interface between the `meshless` executable and its MPI plugin (libmeshless_mpi.so, built
// from stream/mpi_plugin/ into the executable's folder when CMake finds MPI). The executable does not link
// MPI: every command would pay for loading libmpi and its dependencies at start-up (about 6 ms of
// CPU per process, measured: 13 ms with, 7 ms without), which pipes of stages and nightly batches
// pay once per process. stream/mpi_session.cpp loads the plugin (dlopen, RTLD_GLOBAL so that Open MPI
// finds its own components) only when the process was launched by mpirun.
// Header-only and ABI-neutral apart from std::vector and std::optional (plugin and executable come
// from one build; the symbol's version changes with the interface). Thread-safety: the plugin
// serialises its MPI calls (MPI_THREAD_SERIALIZED and one mutex, never held while waiting), so the
// deal's requests and grants may run on other threads than the stream's sends and receives.
#pragma once
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

namespace meshless {

class MpiBackend {
public:
    virtual ~MpiBackend() = default;
    virtual int rank() const = 0;
    virtual int size() const = 0;
    /// Element-wise sum of in[0..n) over ranks into out (rank 0). Collective.
    virtual void sum_to_root(const std::int64_t* in, std::int64_t* out, int n) = 0;
    /// Ends every rank of the job with `code` (does not return).
    [[noreturn]] virtual void abort(int code) = 0;
    /// The byte channel to rank 0 (see stream/mpi_session.hpp MpiChannel); one open at a time.
    virtual void open_channel(int window) = 0;
    virtual void close_channel() = 0;
    virtual void send_to_root(std::vector<std::byte> message) = 0;
    virtual void receive_from(int rank, std::vector<std::byte>& message) = 0;
    virtual void flush() = 0;
    /// Every rank's bytes concatenated in rank order, on every rank (collective; kernels/field_params.hpp
    /// FitShare). Throws std::runtime_error when a rank's part exceeds INT_MAX bytes.
    virtual std::vector<std::byte> allgather(const std::byte* mine, std::size_t n) = 0;
    /// The dynamic deal (stream/unit_deal.hpp, RankChannel's contract).
    virtual std::optional<std::size_t> request_unit() = 0;
    virtual std::optional<int> poll_request() = 0;
    virtual void grant(int rank, std::optional<std::size_t> unit) = 0;
};

/// The plugin's one exported function (extern "C", this name): MPI_Init (if not yet) and a backend
/// owned by the caller; deleting it calls MPI_Finalize.
using MpiBackendFactory = MpiBackend* (*)(int* argc, char*** argv);
inline constexpr const char* kMpiBackendSymbol = "meshless_mpi_backend_v3";
/// The plugin's file name, looked up beside the executable.
inline constexpr const char* kMpiPluginFile = "libmeshless_mpi.so";

}  // namespace meshless
