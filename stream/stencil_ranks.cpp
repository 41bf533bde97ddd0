#include "stream/stencil_ranks.hpp"

#include <optional>
#include <stdexcept>

#include "kernels/marching_stencils.hpp"
#include "stream/stencil_source.hpp"
#include "stream/unit_deal.hpp"

namespace meshless {

StencilRankResult run_stencils_rank(const StencilInput& in, double iso, int n, const FieldProjectParams& np, int rank, int ranks,
                                    RankChannel& channel, Sink* out, const RunOptions& opt,
                                    std::function<void(std::exception_ptr)> on_deal_error) {
    if (ranks < 1 || rank < 0 || rank >= ranks) throw std::invalid_argument("run_stencils_rank: bad rank");
    if (rank == 0 && !out) throw std::invalid_argument("run_stencils_rank: rank 0 needs a sink");
    const StencilGrid sg(in.grid.dims);
    const auto rows = static_cast<std::size_t>(sg.count[1] * sg.count[2]);
    UnitList mine;
    std::optional<UnitDealer> dealer;
    if (rank == 0) dealer.emplace(rows, ranks);
    // rank 0 takes its rows from the dealer itself, the others ask rank 0 for theirs
    StencilSource stencils(sg, [&]() -> std::optional<std::size_t> {
        const std::optional<std::size_t> r = rank == 0 ? dealer->take(0) : channel.request_unit();
        if (r) mine.push(*r);
        return r;
    });
    UnitTags tags;
    const std::int64_t row_length = sg.count[0];
    TaggingSource source(stencils, tags, [row_length](const Batch& b) { return static_cast<std::size_t>(b.cells.k0 / row_length); });
    const StencilSeedStage seed(in, iso, n);
    const FieldProjectStage project(in.field, iso, np);
    const Stage* stages[] = {&seed, &project};
    StencilRankResult res;
    if (rank == 0) {
        UnitDealService service(channel, *dealer, ranks, std::move(on_deal_error));
        RankMergeSink sink(channel, tags, rows, [&](std::size_t u) { return dealer->owner(u); }, *out);
        run_pipeline(source, stages, sink, opt);
        service.finish();
        res.rows_per_rank = dealer->dealt_per_rank();
    } else {
        RankSendSink sink(channel, tags, rank, mine);
        run_pipeline(source, stages, sink, opt);
    }
    res.seeds = seed.stats();
    res.newton = project.stats();
    return res;
}

}  // namespace meshless
