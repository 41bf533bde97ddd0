#include "stream/unit_deal.hpp"

#include <algorithm>
#include <chrono>
#include <stdexcept>
#include <string>

namespace meshless {

UnitDealer::UnitDealer(std::size_t units, int ranks)
    : owner_(units, -1), per_rank_(static_cast<std::size_t>(std::max(1, ranks)), 0) {}

std::optional<std::size_t> UnitDealer::take(int rank) {
    std::lock_guard lock(mu_);
    if (next_ >= owner_.size()) return std::nullopt;
    if (rank < 0 || static_cast<std::size_t>(rank) >= per_rank_.size())
        throw std::logic_error("unit deal: rank " + std::to_string(rank) + " outside 0.." + std::to_string(per_rank_.size() - 1));
    owner_[next_] = rank;
    ++per_rank_[static_cast<std::size_t>(rank)];
    return next_++;
}

int UnitDealer::owner(std::size_t unit) const {
    std::lock_guard lock(mu_);
    if (unit >= next_) throw std::logic_error("unit deal: unit " + std::to_string(unit) + " asked for before it was dealt");
    return owner_[unit];
}

std::vector<std::size_t> UnitDealer::dealt_per_rank() const {
    std::lock_guard lock(mu_);
    return per_rank_;
}

void serve_unit_requests(RankChannel& ch, UnitDealer& dealer, int ranks, std::stop_token stop) {
    std::vector<char> told_none(static_cast<std::size_t>(std::max(1, ranks)), 0);
    int left = ranks - 1;
    std::chrono::microseconds pause(5);
    while (left > 0 && !stop.stop_requested()) {
        const std::optional<int> r = ch.poll_request();
        if (!r) {
            std::this_thread::sleep_for(pause);
            pause = std::min(pause * 2, std::chrono::microseconds(200));
            continue;
        }
        pause = std::chrono::microseconds(5);
        if (*r <= 0 || *r >= ranks || told_none[static_cast<std::size_t>(*r)])
            throw std::logic_error("unit deal: a request from rank " + std::to_string(*r) + " of " + std::to_string(ranks) +
                                   (*r > 0 && *r < ranks ? ", already told that none is left" : ""));
        const std::optional<std::size_t> u = dealer.take(*r);
        ch.grant(*r, u);
        if (!u) {
            told_none[static_cast<std::size_t>(*r)] = 1;
            --left;
        }
    }
}

UnitDealService::UnitDealService(RankChannel& ch, UnitDealer& dealer, int ranks, std::function<void(std::exception_ptr)> on_error)
    : thread_([this, &ch, &dealer, ranks, on_error = std::move(on_error)](std::stop_token stop) {
          try {
              serve_unit_requests(ch, dealer, ranks, stop);
          } catch (...) {
              if (on_error) on_error(std::current_exception());
              else error_ = std::current_exception();
          }
      }) {}

UnitDealService::~UnitDealService() {
    thread_.request_stop();  // the jthread joins
}

void UnitDealService::finish() {
    if (thread_.joinable()) thread_.join();
    if (error_) std::rethrow_exception(error_);
}

}  // namespace meshless
