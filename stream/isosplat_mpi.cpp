#include "stream/isosplat_mpi.hpp"

#include "kernels/errors.hpp"
#include "stream/isosplat_ranks.hpp"
#include "stream/mpi_session.hpp"
#include "stream/volume_input.hpp"

namespace meshless {

MpiIsosurfaceResult run_isosplat_mpi(MpiSession& mpi, VolumeInput& in, double iso, Projection mode, const SamplingParams& sp,
                                     int nthreads, const std::string& command_line, const IsosurfaceWriter& write) {
    if (!in.store) throw InvalidArgument("MPI runs need a brick store (.mlb): meshless convert " + in.path + " -o vol.mlb");
    MpiIsosurfaceResult out;
    out.root = mpi.rank() == 0;
    out.ranks = mpi.size();
    out.path = in.path;
    const std::vector<std::size_t> active = in.index->active(iso);
    MpiChannel channel(mpi);
    IsoSplatResult r;
    if (out.root) {
        StreamMeta meta = volume_meta(in, iso, command_line);
        meta.set("projection", to_string(mode));
        out.points = write(meta, [&](Sink& sink) {
            r = run_isosplat_bricks_rank(*in.store, *in.cache, active, 0, mpi.size(), iso, mode, sp, channel, &sink, {nthreads});
        });
    } else {
        r = run_isosplat_bricks_rank(*in.store, *in.cache, active, mpi.rank(), mpi.size(), iso, mode, sp, channel, nullptr, {nthreads});
    }
    const auto sums = mpi.sum_to_root({r.sampling.active_cells, r.sampling.nonfinite_cells, r.projection.too_far, r.projection.flat,
                                       r.projection.missed});
    out.result = r;
    out.result.sampling = {sums[0], sums[1]};
    out.result.projection.too_far = sums[2];
    out.result.projection.flat = sums[3];
    out.result.projection.missed = sums[4];
    return out;
}

}  // namespace meshless
