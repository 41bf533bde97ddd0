#include "cli/errors.hpp"

#include <algorithm>
#include <cstdio>
#include <new>

#include "kernels/errors.hpp"
#include "stream/mpi_session.hpp"

namespace meshless::cli {

int exit_code(const std::exception& e) noexcept {
    if (dynamic_cast<const BrokenPipe*>(&e)) return kExitOk;
    if (dynamic_cast<const UsageError*>(&e) || dynamic_cast<const InvalidArgument*>(&e)) return kExitUsage;
    if (dynamic_cast<const FormatError*>(&e) || dynamic_cast<const IoError*>(&e) || dynamic_cast<const std::bad_alloc*>(&e))
        return kExitData;
    return kExitInternal;
}

std::string error_message(const std::exception& e) {
    if (dynamic_cast<const std::bad_alloc*>(&e)) return "out of memory";
    if (exit_code(e) == kExitInternal) return terminal_safe(std::string("internal error: ") + e.what());
    return terminal_safe(e.what());
}

void end_mpi_job(MpiSession& mpi, const char* command, const std::exception& e) {
    const int code = exit_code(e);
    if (code != kExitOk)
        std::fprintf(stderr, "meshless %s (rank %d of %d): %s\n", command, mpi.rank(), mpi.size(), error_message(e).c_str());
    mpi.abort(code);
}

int end_mpi_run(MpiSession& mpi, const char* command, const std::exception& e) {
    if (mpi.communicated() || exit_code(e) != kExitUsage) end_mpi_job(mpi, command, e);
    if (mpi.rank() == 0) std::fprintf(stderr, "meshless %s: %s\n", command, error_message(e).c_str());
    return kExitUsage;
}

void end_mpi_job(MpiSession& mpi, const char* command, std::exception_ptr e) {
    try {
        std::rethrow_exception(e);
    } catch (const std::exception& x) {
        end_mpi_job(mpi, command, x);
    } catch (...) {
        mpi.abort(kExitInternal);
    }
}

}  // namespace meshless::cli
