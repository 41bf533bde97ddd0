#include "stream/scattered_isosurface_mpi.hpp"

#include <optional>

#include "stream/mpi_session.hpp"

namespace meshless {

FitShare mpi_fit_share(MpiSession& mpi) {
    return FitShare{mpi.rank(), mpi.size(), [&mpi](std::span<const std::byte> mine) { return mpi.allgather(mine); }};
}

ScatteredMpiResult run_scattered_isosurface_mpi(MpiSession& mpi, const ScatteredIsosurfaceInput& in, const Field* field, double iso,
                                                int n, const FieldProjectParams& np, double dedup, int nthreads,
                                                const ScatteredWriter& write,
                                                const std::function<void(std::exception_ptr)>& on_deal_error) {
    std::optional<MpiChannel> channel;  // (none without a field: an empty output)
    if (field) channel.emplace(mpi);
    RankChannel* ch = channel ? &*channel : nullptr;
    StencilRankResult rr;
    ScatteredMpiResult out;
    if (mpi.rank() == 0) {
        out.points = write([&](Sink& sink) {
            rr = run_scattered_isosurface_rank(in, field, iso, n, np, dedup, 0, mpi.size(), ch, &sink, {nthreads}, on_deal_error);
        });
    } else {
        rr = run_scattered_isosurface_rank(in, field, iso, n, np, dedup, mpi.rank(), mpi.size(), ch, nullptr, {nthreads});
    }
    out.totals = sum_stencil_rank_stats(rr, [&mpi](const std::vector<std::int64_t>& v) { return mpi.sum_to_root(v); });
    return out;
}

}  // namespace meshless
