// Built when CMake found no MPI: launches under mpirun are refused with a clear message.
#ifndef MESHLESS_HAVE_MPI
#include <cstdlib>

#include "cli/mpi_session.hpp"
#include "kernels/errors.hpp"

namespace meshless::cli {

int launched_world_size() {
    for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"})
        if (const char* s = std::getenv(v)) return std::max(1, std::atoi(s));
    return 1;
}

bool mpi_built() { return false; }

MpiSession::MpiSession(int*, char***) {
    throw UsageError("this meshless was built without MPI (install libopenmpi-dev and rebuild: scripts/setup.sh build)");
}
MpiSession::~MpiSession() = default;
std::vector<std::byte> MpiSession::gather_to_root(const void*, std::size_t) { return {}; }
std::vector<std::int64_t> MpiSession::sum_to_root(const std::vector<std::int64_t>& v) { return v; }
void MpiSession::abort(int code) { std::exit(code); }

}  // namespace meshless::cli
#endif
