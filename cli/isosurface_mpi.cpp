#include "cli/isosurface_mpi.hpp"

#include <cstdio>

#include "cli/common.hpp"
#include "cli/errors.hpp"
#include "cli/mpi_session.hpp"
#include "stream/isosplat_ranks.hpp"

namespace meshless::cli {

MpiIsosurfaceResult isosurface_mpi(const Args& a, int argc, char** argv, double iso, Projection mode,
                                   const SamplingParams& sp, int nthreads, const IsosurfaceWriter& write) {
    MpiSession mpi(&argc, &argv);
    MpiIsosurfaceResult out;
    out.root = mpi.rank() == 0;
    out.ranks = mpi.size();
    try {
        VolumeInput in = open_volume_input(a);
        if (!in.store)
            throw UsageError("MPI runs need a brick store (.mlb): meshless convert " + in.path + " -o vol.mlb");
        out.path = in.path;
        const std::vector<std::size_t> active = in.index->active(iso);
        MpiChannel channel(mpi);
        IsoSplatResult r;
        if (out.root) {
            warn_if_iso_outside(iso, in.value_range(), in.path);
            StreamMeta meta = volume_meta(in, iso, a.command_line());
            meta.set("projection", to_string(mode));
            out.points = write(meta, [&](Sink& sink) {
                r = run_isosplat_bricks_rank(*in.store, *in.cache, active, 0, mpi.size(), iso, mode, sp, channel, &sink, {nthreads});
            });
        } else {
            r = run_isosplat_bricks_rank(*in.store, *in.cache, active, mpi.rank(), mpi.size(), iso, mode, sp, channel, nullptr,
                                         {nthreads});
        }
        const auto sums = mpi.sum_to_root({r.sampling.active_cells, r.sampling.nonfinite_cells, r.projection.too_far,
                                           r.projection.flat, r.projection.missed});
        out.result = r;
        out.result.sampling = {sums[0], sums[1]};
        out.result.projection.too_far = sums[2];
        out.result.projection.flat = sums[3];
        out.result.projection.missed = sums[4];
        return out;
    } catch (const std::exception& e) {
        // One failing rank ends the job: nothing is renamed into place, every rank exits non-zero.
        // A closed downstream pipe on rank 0 (BrokenPipe, exit 0) is quiet, but the other ranks may
        // wait on it, so it aborts too.
        const int code = exit_code(e);
        if (code != kExitOk)
            std::fprintf(stderr, "meshless isosurface (rank %d of %d): %s\n", mpi.rank(), mpi.size(), error_message(e).c_str());
        mpi.abort(code);
    }
}

}  // namespace meshless::cli
