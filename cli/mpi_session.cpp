// The MPI implementation of cli/mpi_session.hpp (only file that includes mpi.h).
#ifdef MESHLESS_HAVE_MPI
#include "cli/mpi_session.hpp"

#include <mpi.h>

#include <algorithm>
#include <cstdlib>
#include <chrono>
#include <cstring>
#include <thread>
#include <deque>
#include <limits>
#include <stdexcept>

#include "kernels/errors.hpp"

namespace meshless::cli {

int launched_world_size() {
    for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"})
        if (const char* s = std::getenv(v)) return std::max(1, std::atoi(s));
    return 1;
}

bool mpi_built() { return true; }

MpiSession::MpiSession(int* argc, char*** argv) {
    int inited = 0;
    MPI_Initialized(&inited);
    if (!inited) MPI_Init(argc, argv);
    MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
    MPI_Comm_size(MPI_COMM_WORLD, &size_);
}

MpiSession::~MpiSession() {
    int finalized = 0;
    MPI_Finalized(&finalized);
    if (!finalized) MPI_Finalize();
}

std::vector<std::int64_t> MpiSession::sum_to_root(const std::vector<std::int64_t>& v) {
    std::vector<std::int64_t> out(v.size(), 0);
    MPI_Reduce(v.data(), out.data(), static_cast<int>(v.size()), MPI_INT64_T, MPI_SUM, 0, MPI_COMM_WORLD);
    return out;
}

namespace {
constexpr int kStreamTag = 11;

/// Waits for `done()` without spinning a core: MPI's blocking calls busy-poll, which on a machine
/// with fewer free cores than ranks (mpirun --oversubscribe, other jobs) starves the ranks that
/// compute. Polls a few times, then sleeps in growing steps up to 200 us between polls.
template <class Done>
void wait_politely(Done done) {
    for (int i = 0; i < 64; ++i)
        if (done()) return;
    std::chrono::microseconds pause(5);
    while (!done()) {
        std::this_thread::sleep_for(pause);
        pause = std::min(pause * 2, std::chrono::microseconds(200));
    }
}
}  // namespace

struct MpiChannel::Pending {
    struct Message {
        std::vector<std::byte> bytes;
        MPI_Request request;
    };
    std::deque<Message> q;
};

MpiChannel::MpiChannel(const MpiSession&, int window) : pending_(std::make_unique<Pending>()), window_(std::max(1, window)) {}

MpiChannel::~MpiChannel() {
    // normal runs flush; after an error the job is aborted, so nothing is waited for here
    for (auto& m : pending_->q) MPI_Request_free(&m.request);
}

void MpiChannel::send_to_root(std::vector<std::byte> message) {
    if (message.size() > static_cast<std::size_t>(std::numeric_limits<int>::max()))
        throw std::logic_error("MPI channel: message larger than INT_MAX bytes");
    while (pending_->q.size() >= static_cast<std::size_t>(window_)) {
        MPI_Request* req = &pending_->q.front().request;
        wait_politely([&] {
            int flag = 0;
            MPI_Test(req, &flag, MPI_STATUS_IGNORE);
            return flag != 0;
        });
        pending_->q.pop_front();
    }
    auto& m = pending_->q.emplace_back();
    m.bytes = std::move(message);
    MPI_Issend(m.bytes.data(), static_cast<int>(m.bytes.size()), MPI_BYTE, 0, kStreamTag, MPI_COMM_WORLD, &m.request);
}

void MpiChannel::receive_from(int rank, std::vector<std::byte>& message) {
    MPI_Status st;
    wait_politely([&] {
        int flag = 0;
        MPI_Iprobe(rank, kStreamTag, MPI_COMM_WORLD, &flag, &st);
        return flag != 0;
    });
    int n = 0;
    MPI_Get_count(&st, MPI_BYTE, &n);
    message.resize(static_cast<std::size_t>(n));
    MPI_Recv(message.data(), n, MPI_BYTE, rank, kStreamTag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
}

void MpiChannel::flush() {
    for (auto& m : pending_->q)
        wait_politely([&] {
            int flag = 0;
            MPI_Test(&m.request, &flag, MPI_STATUS_IGNORE);
            return flag != 0;
        });
    pending_->q.clear();
}

void MpiSession::abort(int code) {
    MPI_Abort(MPI_COMM_WORLD, code);
    std::exit(code);
}

}  // namespace meshless::cli
#endif
