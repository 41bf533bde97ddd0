// A point store's points and MPU field over a range of z, the pieces that run a point store (.mlc,
// formats/point_store.hpp) slab by slab within a memory budget (docs/architecture.md, "Fields out of
// core"): the scattered isosurface (stream/scattered_store_isosurface.hpp) and the field queries of
// a store (stream/store_field_queries.hpp) share them.
//
// A slab answers for the queries whose z lies in its query range (x and y anywhere in the box its
// region is given). It loads the store's points within a halo of that range — the points inside the
// loaded z range of the bricks that meet it, and every point of the bricks a lacking ball asked for
// (`extra`) — and the MPU field (dissertation section 5.5) built over them in the whole set's frame
// (kernels/field_region.hpp, the plan's cell counts bounding the points not loaded) equals the whole
// set's field over the query box when MpuField::region_exact() says so; otherwise the bricks its
// lacking balls meet are flagged (add_lacking_bricks) and the slab is loaded again.
// Units: world. Memory: the index, 4 bytes a brick listing and a stamp of 8 bytes a brick.
// Throws FormatError and IoError from the store (naming the file and the brick).
#pragma once
#include <array>
#include <cstdint>
#include <mutex>
#include <utility>
#include <vector>

#include "formats/point_store.hpp"
#include "kernels/field_params.hpp"
#include "kernels/field_region.hpp"
#include "kernels/mpu_field.hpp"
#include "stream/scattered_store_isosurface.hpp"
#include "stream/stage.hpp"

namespace meshless {

/// The store's bricks in a uniform grid over its bounds (each listed in the cells its box meets),
/// to find the bricks a ball meets without scanning them all.
class StoreBrickIndex {
public:
    explicit StoreBrickIndex(const PointStore& store);
    /// Calls f(i) once for every brick whose box meets the ball (c, r). Not thread-safe.
    template <class F>
    void meeting_ball(const Vec3& c, double r, F&& f) const {
        const auto rc = cells(c - Vec3{r, r, r}, c + Vec3{r, r, r});
        ++tick_;
        for (std::int64_t k = rc[0][2]; k <= rc[1][2]; ++k)
            for (std::int64_t j = rc[0][1]; j <= rc[1][1]; ++j)
                for (std::int64_t x = rc[0][0]; x <= rc[1][0]; ++x) {
                    const std::size_t cell = static_cast<std::size_t>(x + side_ * (j + side_ * k));
                    for (std::size_t q = first_[cell]; q < first_[cell + 1]; ++q) {
                        const std::uint32_t i = list_[q];
                        if (stamp_[i] == tick_) continue;
                        stamp_[i] = tick_;
                        if (ball_meets(bricks_[i], c, r)) f(i);
                    }
                }
    }

private:
    static bool ball_meets(const PointBrickEntry& b, const Vec3& c, double r);
    std::array<std::array<std::int64_t, 3>, 2> cells(const Vec3& lo, const Vec3& hi) const;
    const std::vector<PointBrickEntry>& bricks_;
    Vec3 lo_;
    double inv_[3] = {0, 0, 0};
    std::int64_t side_ = 1;
    std::vector<std::size_t> first_;
    std::vector<std::uint32_t> list_;
    mutable std::vector<std::uint64_t> stamp_;
    mutable std::uint64_t tick_ = 0;
};

/// One slab: the z range of its queries and the bricks it loads.
struct StoreSlab {
    std::array<double, 2> query{}, loaded{};  // z ranges, world (loaded: +-infinity beyond the data)
    std::vector<char> in;                     // per brick: read (1: its points in `loaded`, 2: all)
    std::uint64_t points = 0;                 // at least the points it loads (an estimate from the plan)
};

/// The slab answering for z in `query` with a halo of `halo` world units along z, the bricks that
/// `extra` flags read whole.
StoreSlab store_slab(const PointStore& store, const ScatteredStorePlan& plan, const std::array<double, 2>& query, double halo,
                     const std::vector<char>& extra);

/// The points of the slab's bricks, in store order (the order the in-memory path reads); adds the
/// reading's seconds to `seconds`.
PointSet load_store_slab(const PointStore& store, const StoreSlab& slab, double& seconds);

/// The first halo: two MPU fit spheres at the mean density (a leaf whose blend sphere meets the
/// query box fits the points of its sphere, which holds at most N points: radius (3N / 4 pi rho)^(1/3)
/// where the density is rho), at least two grid cells; lacking balls add what uneven data needs.
double store_first_halo(const ScatteredStorePlan& plan, const FieldParams& field_params);

/// A slab's FieldRegion: the query box (x-y as given, z the slab's query range), its loaded z
/// range, and the store's counts as the bounds of the points it lacks. The field is built on several
/// threads: each count reads the brick index under a lock.
class StoreSlabRegion {
public:
    StoreSlabRegion(const PointStore& store, const ScatteredStorePlan& plan, const StoreBrickIndex& index, const StoreSlab& slab,
                    const std::array<Vec3, 2>& query_xy);
    StoreSlabRegion(const StoreSlabRegion&) = delete;
    StoreSlabRegion& operator=(const StoreSlabRegion&) = delete;
    FieldRegion region;

private:
    std::mutex lock_;
};

/// Flags the bricks the field's lacking balls meet in `extra` and remembers the balls in `seen`;
/// returns the bricks newly flagged.
std::size_t add_lacking_bricks(const MpuField& field, const StoreBrickIndex& index, std::vector<char>& extra,
                               std::vector<std::pair<Vec3, double>>& seen);

/// The bricks above world z = from that the lacking balls of earlier slabs meet (the balls wholly
/// below are dropped from `seen`): uneven data asks for the same far points slab after slab.
std::vector<char> bricks_still_lacking(const PointStore& store, const StoreBrickIndex& index,
                                       std::vector<std::pair<Vec3, double>>& seen, double from);

/// A slab field's build figures added to a run's: its locals by outcome, and the largest field.
void add_slab_field_stats(FieldBuildStats& to, const FieldBuildStats& s);

/// Keeps a slab's batches (of one payload kind) until the slab is known to be exact.
class BatchBuffer final : public Sink {
public:
    explicit BatchBuffer(Payload kind) : kind_(kind) {}
    PayloadSet takes() const override { return kind_; }
    void consume(Batch&& b) override { batches.push_back(std::move(b)); }
    void finish() override {}
    /// The batches to `sink`, numbered on from `seq` (which moves past them); the buffer is left empty.
    void forward(Sink& sink, std::uint64_t& seq);
    std::vector<Batch> batches;

private:
    Payload kind_;
};

}  // namespace meshless
