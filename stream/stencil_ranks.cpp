#include "stream/stencil_ranks.hpp"

#include <stdexcept>

#include "kernels/marching_stencils.hpp"
#include "stream/stencil_source.hpp"

namespace meshless {

StencilRankResult run_stencils_rank(const StencilInput& in, double iso, int n, const FieldProjectParams& np, int rank, int ranks,
                                    RankChannel& channel, Sink* out, const RunOptions& opt) {
    if (ranks < 1 || rank < 0 || rank >= ranks) throw std::invalid_argument("run_stencils_rank: bad rank");
    if (rank == 0 && !out) throw std::invalid_argument("run_stencils_rank: rank 0 needs a sink");
    const StencilGrid sg(in.grid.dims);
    const auto rows = static_cast<std::size_t>(sg.count[1] * sg.count[2]);
    const std::vector<std::size_t> units = units_of_rank(rows, rank, ranks);
    StencilSource stencils(sg, units);
    UnitTags tags;
    const std::int64_t row_length = sg.count[0];
    TaggingSource source(stencils, tags, [row_length](const Batch& b) { return static_cast<std::size_t>(b.cells.k0 / row_length); });
    const StencilSeedStage seed(in, iso, n);
    const FieldProjectStage project(in.field, iso, np);
    const Stage* stages[] = {&seed, &project};
    if (rank == 0) {
        RankMergeSink sink(channel, tags, rows, ranks, *out);
        run_pipeline(source, stages, sink, opt);
    } else {
        RankSendSink sink(channel, tags, rank, units);
        run_pipeline(source, stages, sink, opt);
    }
    return {seed.stats(), project.stats()};
}

}  // namespace meshless
