// The MPI plugin (libmeshless_mpi.so, see stream/mpi_backend.hpp): the only code that includes
// mpi.h. Loaded by stream/mpi_session.cpp when `meshless` runs under mpirun.
#include "stream/mpi_backend.hpp"

#include <mpi.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <deque>
#include <limits>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>

namespace meshless {

namespace {
constexpr int kStreamTag = 11, kRequestTag = 12, kGrantTag = 13;
constexpr std::uint64_t kNoUnit = ~std::uint64_t{0};

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

class OpenMpiBackend final : public MpiBackend {
public:
    OpenMpiBackend(int* argc, char*** argv) {
        int inited = 0;
        MPI_Initialized(&inited);
        if (!inited) {
            int provided = MPI_THREAD_SINGLE;
            MPI_Init_thread(argc, argv, MPI_THREAD_SERIALIZED, &provided);
            serialized_ = provided >= MPI_THREAD_SERIALIZED;
        } else {
            int provided = MPI_THREAD_SINGLE;
            MPI_Query_thread(&provided);
            serialized_ = provided >= MPI_THREAD_SERIALIZED;
        }
        MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
        MPI_Comm_size(MPI_COMM_WORLD, &size_);
    }
    ~OpenMpiBackend() override {
        close_channel();
        int finalized = 0;
        MPI_Finalized(&finalized);
        if (!finalized) MPI_Finalize();
    }
    int rank() const override { return rank_; }
    int size() const override { return size_; }
    void sum_to_root(const std::int64_t* in, std::int64_t* out, int n) override {
        MPI_Reduce(in, out, n, MPI_INT64_T, MPI_SUM, 0, MPI_COMM_WORLD);
    }
    [[noreturn]] void abort(int code) override {
        // possibly from the deal's thread while another waits in a poll loop: serialised like every call,
        // and no exit handlers run under the other threads' feet
        std::lock_guard lock(mu_);
        MPI_Abort(MPI_COMM_WORLD, code);
        std::_Exit(code);
    }
    void open_channel(int window) override {
        close_channel();
        window_ = std::max(1, window);
    }
    void close_channel() override {
        // normal runs flush; after an error the job is aborted, so nothing is waited for here. A
        // freed request's send may still be under way: its bytes must outlive it (freeing them made
        // rank 0 read another allocation's bytes as a message header), so they are kept until exit.
        for (auto& m : q_) MPI_Request_free(&m.request);
        for (auto& m : q_) abandoned_.push_back(std::move(m.bytes));
        q_.clear();
    }

    void send_to_root(std::vector<std::byte> message) override {
        if (message.size() > static_cast<std::size_t>(std::numeric_limits<int>::max()))
            throw std::logic_error("MPI channel: message larger than INT_MAX bytes");
        while (q_.size() >= static_cast<std::size_t>(window_)) {
            wait_politely([&] { return test(q_.front().request); });
            q_.pop_front();
        }
        auto& m = q_.emplace_back();
        m.bytes = std::move(message);
        std::lock_guard lock(mu_);
        MPI_Issend(m.bytes.data(), static_cast<int>(m.bytes.size()), MPI_BYTE, 0, kStreamTag, MPI_COMM_WORLD, &m.request);
    }

    void receive_from(int rank, std::vector<std::byte>& message) override {
        MPI_Status st;
        wait_politely([&] {
            std::lock_guard lock(mu_);
            int flag = 0;
            MPI_Iprobe(rank, kStreamTag, MPI_COMM_WORLD, &flag, &st);
            return flag != 0;
        });
        int n = 0;
        std::lock_guard lock(mu_);
        MPI_Get_count(&st, MPI_BYTE, &n);
        message.resize(static_cast<std::size_t>(n));
        MPI_Recv(message.data(), n, MPI_BYTE, rank, kStreamTag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    }

    void flush() override {
        for (auto& m : q_) wait_politely([&] { return test(m.request); });
        q_.clear();
    }

    std::vector<std::byte> allgather(const std::byte* mine, std::size_t n) override {
        require_serialized();  // called from a oneTBB task, maybe not the main thread
        std::lock_guard lock(mu_);
        const std::uint64_t mine_n = n;
        std::vector<std::uint64_t> sizes(static_cast<std::size_t>(size_));
        MPI_Allgather(&mine_n, 1, MPI_UINT64_T, sizes.data(), 1, MPI_UINT64_T, MPI_COMM_WORLD);
        std::vector<int> counts(sizes.size()), displs(sizes.size());
        std::uint64_t total = 0;
        for (std::size_t r = 0; r < sizes.size(); ++r) {
            if (sizes[r] > static_cast<std::uint64_t>(std::numeric_limits<int>::max()) ||
                total + sizes[r] > static_cast<std::uint64_t>(std::numeric_limits<int>::max()))
                throw std::runtime_error("MPI gather: " + std::to_string(total + sizes[r]) + " bytes, beyond MPI's INT_MAX counts");
            counts[r] = static_cast<int>(sizes[r]);
            displs[r] = static_cast<int>(total);
            total += sizes[r];
        }
        std::vector<std::byte> all(total);
        MPI_Allgatherv(mine, static_cast<int>(n), MPI_BYTE, all.data(), counts.data(), displs.data(), MPI_BYTE, MPI_COMM_WORLD);
        return all;
    }

    std::optional<std::size_t> request_unit() override {
        require_serialized();
        const std::uint64_t ask = 0;
        MPI_Request req;
        {
            std::lock_guard lock(mu_);
            MPI_Isend(&ask, 1, MPI_UINT64_T, 0, kRequestTag, MPI_COMM_WORLD, &req);
        }
        std::uint64_t unit = kNoUnit;
        MPI_Request got;
        {
            std::lock_guard lock(mu_);
            MPI_Irecv(&unit, 1, MPI_UINT64_T, 0, kGrantTag, MPI_COMM_WORLD, &got);
        }
        wait_politely([&] { return test(req); });
        wait_politely([&] { return test(got); });
        if (unit == kNoUnit) return std::nullopt;
        return static_cast<std::size_t>(unit);
    }

    std::optional<int> poll_request() override {
        require_serialized();
        std::lock_guard lock(mu_);
        int flag = 0;
        MPI_Status st;
        MPI_Iprobe(MPI_ANY_SOURCE, kRequestTag, MPI_COMM_WORLD, &flag, &st);
        if (!flag) return std::nullopt;
        std::uint64_t ask = 0;
        MPI_Recv(&ask, 1, MPI_UINT64_T, st.MPI_SOURCE, kRequestTag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
        return st.MPI_SOURCE;
    }

    void grant(int rank, std::optional<std::size_t> unit) override {
        require_serialized();
        const std::uint64_t u = unit ? static_cast<std::uint64_t>(*unit) : kNoUnit;
        MPI_Request req;
        {
            std::lock_guard lock(mu_);
            MPI_Isend(&u, 1, MPI_UINT64_T, rank, kGrantTag, MPI_COMM_WORLD, &req);
        }
        wait_politely([&] { return test(req); });  // the rank waits for it in request_unit
    }

private:
    bool test(MPI_Request& req) {
        std::lock_guard lock(mu_);
        int flag = 0;
        MPI_Test(&req, &flag, MPI_STATUS_IGNORE);
        return flag != 0;
    }
    void require_serialized() const {
        if (!serialized_)
            throw std::runtime_error("this MPI library does not provide MPI_THREAD_SERIALIZED, which the dynamic deal of work needs");
    }
    std::mutex mu_;  // every MPI call (MPI_THREAD_SERIALIZED); never held while waiting
    bool serialized_ = false;
    struct Message {
        std::vector<std::byte> bytes;
        MPI_Request request;
    };
    std::deque<Message> q_;
    std::vector<std::vector<std::byte>> abandoned_;  // close_channel(): bytes of sends still in flight
    int window_ = 4;
    int rank_ = 0, size_ = 1;
};

}  // namespace meshless

extern "C" __attribute__((visibility("default"))) meshless::MpiBackend* meshless_mpi_backend_v3(int* argc, char*** argv) {
    return new meshless::OpenMpiBackend(argc, argv);
}
