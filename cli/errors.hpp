// The CLI's own error type and the one mapping from exceptions to exit codes, used by every
// executable (meshless, its MPI path, meshless-bench). The libraries below cli/ throw their own
// types (kernels/errors.hpp) and never UsageError.
//   exit 0: success; a closed downstream pipe (BrokenPipe: quiet, nothing printed)
//   exit 1: UsageError (bad flag, missing argument, malformed option value) and the libraries'
//           InvalidArgument (a parameter outside a function's domain, usually from the command line)
//   exit 2: FormatError (bad input data), IoError (the environment failed), std::bad_alloc
//   exit 3: anything else (an internal error)
//   exit 4: an empty result under --fail-empty (isosurface, mc, generate: no point, triangle or
//           sample; batch: an isovalue of some volume gave none) — the outputs are written, valid
//           and empty; without --fail-empty the same run warns and exits 0 (cli/common.hpp)
// Thread-safety: stateless functions.
#pragma once
#include <exception>
#include <stdexcept>
#include <string>
#include <string_view>

#include "formats/terminal_safe.hpp"
#include "kernels/errors.hpp"
#include "stream/pipe_closure.hpp"

namespace meshless {
class MpiSession;
}

namespace meshless::cli {

/// The user asked for something inconsistent on the command line (bad flag, missing argument,
/// malformed value). Thrown by cli/ only.
struct UsageError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

inline constexpr int kExitOk = 0;
inline constexpr int kExitUsage = 1;
inline constexpr int kExitData = 2;
inline constexpr int kExitInternal = 3;
inline constexpr int kExitEmpty = 4;

/// The exit code for an exception that ended a command (see the table above).
int exit_code(const std::exception& e) noexcept;

/// The one-line message for it: what(), "out of memory" for std::bad_alloc, prefixed
/// "internal error: " when exit_code(e) is kExitInternal; passed through terminal_safe (formats/terminal_safe.hpp; the
/// readers escape what they quote from files; this is the last line of defence).
std::string error_message(const std::exception& e);

/// Under mpirun, one failing rank ends the job (nothing is renamed into place, every rank exits
/// non-zero): prints "meshless COMMAND (rank R of N): MESSAGE" on stderr (not for a closed downstream
/// pipe, exit 0, which still aborts: the other ranks may wait on it) and aborts with exit_code(e).
[[noreturn]] void end_mpi_job(MpiSession& mpi, const char* command, const std::exception& e);
/// The same for an error caught on another thread (an exception not derived from std::exception: exit 3, quietly).
[[noreturn]] void end_mpi_job(MpiSession& mpi, const char* command, std::exception_ptr e);
/// A usage error under mpirun (UsageError or InvalidArgument: exit 1). Met before this rank talked to
/// any other (MpiSession::communicated), it is the options' fault and every rank meets it alike: rank 0
/// prints "meshless COMMAND: MESSAGE" alone and every rank returns kExitUsage for a clean MPI_Finalize
/// (no MPI_ABORT; the launcher still says that a process exited non-zero). Met later (an output
/// checked by rank 0 alone while the others work), it ends the job as end_mpi_job does.
int end_mpi_run(MpiSession& mpi, const char* command, const std::exception& e);

}  // namespace meshless::cli
