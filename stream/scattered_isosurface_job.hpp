// The scattered-data isosurface as one job of a front end (dissertation chapter 5, sections
// 5.3-5.6), run into the outputs of an IsosurfaceJob (stream/isosurface_job.hpp: a PLY/VTP and/or a
// PNG) with the progress of the stencils handed out, its warnings and its --stats block: points
// binned in memory with their field (stream/scattered_isosurface.hpp), a point store slab by slab
// within a memory budget (stream/scattered_store_isosurface.hpp), or points dealt to the ranks of
// mpirun (stream/scattered_isosurface_mpi.hpp). What `meshless isosurface POINTS` runs once its
// options are checked (and any other front end). Units: isovalue in the points' value units, dedup a
// fraction of the point radius, memory in bytes. Throws what those recipes and
// stream/point_outputs.hpp throw.
#pragma once
#include <cstdio>
#include <exception>
#include <functional>
#include <optional>
#include <string>

#include "formats/point_store.hpp"
#include "stream/isosurface_job.hpp"
#include "stream/scattered_isosurface.hpp"
#include "stream/scattered_store_isosurface.hpp"

namespace meshless {

class MpiSession;

/// In memory: the isosurface of `in` onto the field `f` (fit_scattered_field; f.meta gets the
/// `dedup` key when dedup > 0), then the warning of seeds that did not converge (to `warn`) and the
/// statistics naming `cmd`. With dedup > 0 the picture is drawn on the sink side, in sequence order.
/// Returns the points written.
std::size_t run_scattered_isosurface_job(const IsosurfaceJob& j, double dedup, const ScatteredIsosurfaceInput& in,
                                         IsosurfaceField& f, const char* cmd, std::FILE* warn = stderr);

/// Under mpirun (collective: every rank calls it): the stencil rows dealt to the ranks, rank 0
/// writing j's outputs; the statistics summed to rank 0. on_deal_error: as run_scattered_isosurface_mpi
/// (a front end ends the job there).
void run_scattered_isosurface_mpi_job(const IsosurfaceJob& j, double dedup, MpiSession& mpi, const ScatteredIsosurfaceInput& in,
                                      const IsosurfaceField& f, const char* cmd,
                                      const std::function<void(std::exception_ptr)>& on_deal_error);

/// A point store with the mpu field, slab by slab within sp.memory_bytes: `plan` (plan_scattered_store),
/// the metadata made here (scattered_store_meta with the projection's keys and the frame widened by
/// j.np.seed_max_travel). memory_option: the budget as the user gave it, when given: a budget near
/// the least that runs (many slabs re-reading the points) is then warned about (to `warn`).
/// Returns the points written.
std::size_t run_scattered_store_job(const IsosurfaceJob& j, double dedup, const PointStore& store, const ScatteredStorePlan& plan,
                                    const FieldParams& field_params, const ScatteredStoreParams& sp, const std::string& producer,
                                    const std::optional<std::string>& memory_option, const char* cmd, std::FILE* warn = stderr);

/// A point store under mpirun (collective: every rank calls it): each rank runs its stencil layers
/// slab by slab within sp.memory_bytes (its own budget: stream/scattered_store_ranks.hpp), rank 0
/// writing j's outputs in the single-process order (the bytes of run_scattered_store_job); the
/// statistics, with each rank's points loaded and peak RSS, summed to rank 0 (and the warning of
/// run_scattered_store_job about thin slabs, over all ranks' slabs). Returns the points written (rank
/// 0; 0 elsewhere). A rank's error is thrown on that rank (a front end ends the job).
std::size_t run_scattered_store_mpi_job(const IsosurfaceJob& j, double dedup, MpiSession& mpi, const PointStore& store,
                                        const ScatteredStorePlan& plan, const FieldParams& field_params, const ScatteredStoreParams& sp,
                                        const std::string& producer, const std::optional<std::string>& memory_option, const char* cmd);

}  // namespace meshless
