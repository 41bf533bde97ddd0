// Ranks as threads of one test process: an in-memory RankChannel with the MPI channel's contract
// (stream/rank_merge.hpp): per-rank message queues to rank 0 holding at most `window` unreceived
// messages (a sender blocks when its queue is full), and the dynamic deal's requests and grants
// (stream/unit_deal.hpp). Records each queue's deepest fill and how many requests were made.
#pragma once
#include <algorithm>
#include <condition_variable>
#include <cstddef>
#include <deque>
#include <mutex>
#include <optional>
#include <vector>

#include "stream/rank_merge.hpp"

namespace meshless::test {

struct Hub {
    explicit Hub(int ranks, std::size_t window)
        : q(static_cast<std::size_t>(ranks)), max_depth(q.size(), 0), grants(q.size()), window(window) {}
    std::mutex m;
    std::condition_variable cv;
    std::vector<std::deque<std::vector<std::byte>>> q;
    std::vector<std::size_t> max_depth;
    std::deque<int> requests;                                  // ranks waiting for a unit, in order
    std::vector<std::deque<std::optional<std::size_t>>> grants;  // answers not yet taken, per rank
    std::size_t requests_made = 0;
    std::size_t window;
};

class HubChannel final : public RankChannel {
public:
    HubChannel(Hub& h, int rank) : h_(h), r_(static_cast<std::size_t>(rank)) {}
    void send_to_root(std::vector<std::byte> m) override {
        std::unique_lock lock(h_.m);
        h_.cv.wait(lock, [&] { return h_.q[r_].size() < h_.window; });
        h_.q[r_].push_back(std::move(m));
        h_.max_depth[r_] = std::max(h_.max_depth[r_], h_.q[r_].size());
        h_.cv.notify_all();
    }
    void receive_from(int rank, std::vector<std::byte>& m) override {
        std::unique_lock lock(h_.m);
        auto& q = h_.q[static_cast<std::size_t>(rank)];
        h_.cv.wait(lock, [&] { return !q.empty(); });
        m = std::move(q.front());
        q.pop_front();
        h_.cv.notify_all();
    }
    void flush() override {
        std::unique_lock lock(h_.m);
        h_.cv.wait(lock, [&] { return h_.q[r_].empty(); });
    }
    std::optional<std::size_t> request_unit() override {
        std::unique_lock lock(h_.m);
        h_.requests.push_back(static_cast<int>(r_));
        ++h_.requests_made;
        h_.cv.notify_all();
        h_.cv.wait(lock, [&] { return !h_.grants[r_].empty(); });
        const std::optional<std::size_t> u = h_.grants[r_].front();
        h_.grants[r_].pop_front();
        return u;
    }
    std::optional<int> poll_request() override {
        std::lock_guard lock(h_.m);
        if (h_.requests.empty()) return std::nullopt;
        const int r = h_.requests.front();
        h_.requests.pop_front();
        return r;
    }
    void grant(int rank, std::optional<std::size_t> unit) override {
        std::lock_guard lock(h_.m);
        h_.grants[static_cast<std::size_t>(rank)].push_back(unit);
        h_.cv.notify_all();
    }

private:
    Hub& h_;
    std::size_t r_;
};

}  // namespace meshless::test
