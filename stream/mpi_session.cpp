// stream/mpi_session.hpp over the MPI plugin (stream/mpi_backend.hpp): the executable itself does not
// link MPI; the plugin is loaded only when a session starts (under mpirun).
#include "stream/mpi_session.hpp"

#include <dlfcn.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <system_error>

#include "kernels/errors.hpp"

namespace meshless {

namespace {
/// The plugin's path: beside the running executable.
std::string plugin_path() {
    std::error_code ec;
    const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
    if (ec) return kMpiPluginFile;
    return (exe.parent_path() / kMpiPluginFile).string();
}
}  // namespace

int launched_world_size() {
    for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"})
        if (const char* s = std::getenv(v)) return std::max(1, std::atoi(s));
    return 1;
}

int launched_world_rank() {
    for (const char* v : {"OMPI_COMM_WORLD_RANK", "PMI_RANK"})
        if (const char* s = std::getenv(v)) return std::max(0, std::atoi(s));
    return 0;
}

int launched_local_size() {
    for (const char* v : {"OMPI_COMM_WORLD_LOCAL_SIZE", "MPI_LOCALNRANKS", "PMI_LOCAL_SIZE"})
        if (const char* s = std::getenv(v)) return std::max(1, std::atoi(s));
    return launched_world_size();
}

bool mpi_built() { return ::access(plugin_path().c_str(), R_OK) == 0; }

MpiSession::MpiSession(int* argc, char*** argv) {
    const std::string path = plugin_path();
    if (!mpi_built())
        throw InvalidArgument("this meshless has no MPI plugin (" + path +
                         " is missing: install libopenmpi-dev and rebuild, scripts/setup.sh build)");
    // RTLD_GLOBAL: Open MPI dlopens its own components, which need libmpi's symbols
    plugin_ = ::dlopen(path.c_str(), RTLD_NOW | RTLD_GLOBAL);
    if (!plugin_) throw InvalidArgument(path + ": cannot load the MPI plugin (" + std::string(::dlerror()) + ")");
    const auto make = reinterpret_cast<MpiBackendFactory>(::dlsym(plugin_, kMpiBackendSymbol));
    if (!make) throw InvalidArgument(path + ": not a meshless MPI plugin (no " + std::string(kMpiBackendSymbol) + ")");
    backend_.reset(make(argc, argv));
    rank_ = backend_->rank();
    size_ = backend_->size();
}

MpiSession::~MpiSession() {
    backend_.reset();  // MPI_Finalize; the plugin stays loaded (Open MPI may still hold threads/handlers)
}

std::vector<std::int64_t> MpiSession::sum_to_root(const std::vector<std::int64_t>& v) {
    note_communication();
    std::vector<std::int64_t> out(v.size(), 0);
    backend_->sum_to_root(v.data(), out.data(), static_cast<int>(v.size()));
    return out;
}

std::vector<std::byte> MpiSession::allgather(std::span<const std::byte> mine) {
    note_communication();
    return backend_->allgather(mine.data(), mine.size());
}

void MpiSession::abort(int code) {
    backend_->abort(code);
    std::exit(code);  // not reached: the backend does not return
}

MpiChannel::MpiChannel(const MpiSession& s, int window) : backend_(s.backend()) {
    s.note_communication();
    backend_.open_channel(window);
}
MpiChannel::~MpiChannel() { backend_.close_channel(); }
void MpiChannel::send_to_root(std::vector<std::byte> message) { backend_.send_to_root(std::move(message)); }
void MpiChannel::receive_from(int rank, std::vector<std::byte>& message) { backend_.receive_from(rank, message); }
void MpiChannel::flush() { backend_.flush(); }
std::optional<std::size_t> MpiChannel::request_unit() { return backend_.request_unit(); }
std::optional<int> MpiChannel::poll_request() { return backend_.poll_request(); }
void MpiChannel::grant(int rank, std::optional<std::size_t> unit) { backend_.grant(rank, unit); }

}  // namespace meshless
