// Built when CMake found no MPI: launches under mpirun are refused with a clear message.
#ifndef MESHLESS_HAVE_MPI
#include <cstdlib>

#include "cli/errors.hpp"
#include "cli/mpi_session.hpp"

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
std::vector<std::int64_t> MpiSession::sum_to_root(const std::vector<std::int64_t>& v) { return v; }
void MpiSession::abort(int code) { std::exit(code); }

struct MpiChannel::Pending {};
MpiChannel::MpiChannel(const MpiSession&, int window) : window_(window) {
    throw UsageError("this meshless was built without MPI");
}
MpiChannel::~MpiChannel() = default;
void MpiChannel::send_to_root(std::vector<std::byte>) {}
void MpiChannel::receive_from(int, std::vector<std::byte>&) {}
void MpiChannel::flush() {}

}  // namespace meshless::cli
#endif
