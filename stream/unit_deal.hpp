// The dynamic deal of work units over ranks: the dissertation's master/worker (section 5.7: "a simple
// master-slave architecture, where a single master monitors the progress of slaves generating the
// isosurface geometry"): a rank asks for its next unit when it is ready for one, so that uneven
// units (stencil rows through dense and through empty regions) balance. Rank 0 is master and worker at once: a
// UnitDealService thread answers the other ranks' requests (RankChannel::request_unit /
// poll_request / grant) from the same UnitDealer that rank 0's own source takes its units from.
// Units are dealt one at a time in increasing order, so every unit below the one a rank is given
// has an owner already: rank 0's RankMergeSink (stream/rank_merge.hpp) asks UnitDealer::owner for
// the units before each of its own and, at its end, for all of them (its source is exhausted only
// when the dealer is), and writes the single-process sequence whatever the deal was.
// Thread-safety: UnitDealer is (one mutex); the service runs serve_unit_requests on its own thread.
// Throws: UnitDealer::owner std::logic_error for a unit not dealt; the service rethrows what the
// channel threw from finish().
#pragma once
#include <cstddef>
#include <cstdint>
#include <exception>
#include <functional>
#include <mutex>
#include <optional>
#include <stop_token>
#include <thread>
#include <vector>

#include "stream/rank_merge.hpp"

namespace meshless {

/// Rank 0's record of the deal: units 0..units-1, handed out in increasing order.
class UnitDealer {
public:
    UnitDealer(std::size_t units, int ranks);
    /// The next unit, recorded as `rank`'s; nullopt when every unit is dealt.
    std::optional<std::size_t> take(int rank);
    /// The rank unit u was dealt to (std::logic_error when it was not dealt yet).
    int owner(std::size_t unit) const;
    std::size_t units() const { return owner_.size(); }
    /// Units dealt to each rank so far (statistics: how the deal balanced).
    std::vector<std::size_t> dealt_per_rank() const;

private:
    mutable std::mutex mu_;
    std::size_t next_ = 0;
    std::vector<std::int32_t> owner_;
    std::vector<std::size_t> per_rank_;
};

/// Rank 0: answers requests from ranks 1..ranks-1 with dealer.take(rank) until each of them has been
/// told that none is left, or `stop` is requested. Between empty polls it sleeps (5 us growing to
/// 200 us), so it never takes a core from the rank's workers.
void serve_unit_requests(RankChannel& ch, UnitDealer& dealer, int ranks, std::stop_token stop);

/// serve_unit_requests on its own thread, from construction to finish() (or destruction, which stops
/// it: an error path does not wait for the other ranks).
class UnitDealService {
public:
    /// on_error: called on the service's thread with what it threw; without it finish() rethrows
    /// it, but the ranks waiting for a unit (and rank 0's merge, waiting for theirs) then wait
    /// forever, so give it wherever the other ranks are other processes (MPI: end the job).
    UnitDealService(RankChannel& ch, UnitDealer& dealer, int ranks, std::function<void(std::exception_ptr)> on_error = {});
    ~UnitDealService();
    UnitDealService(const UnitDealService&) = delete;
    UnitDealService& operator=(const UnitDealService&) = delete;
    /// Waits until every other rank has been told that none is left; rethrows the service's error.
    void finish();

private:
    std::exception_ptr error_;
    std::jthread thread_;
};

}  // namespace meshless
