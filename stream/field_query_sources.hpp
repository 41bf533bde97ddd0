// Sources of field queries (RecordKind::query batches) for probe / slice / resample
// (dissertation chapters 4-5 and 7: looking at a fitted field directly):
//   QueryListSource    given positions (--at, --at-file), in order
//   PlaneRasterSource  the pixel centres of an axis-aligned plane raster, row by row from the top
//   GridRasterSource   the samples of a regular grid, x fastest, then y, then z
// Each batch holds at most `batch_queries` positions (default 4096, the granularity the field
// commands evaluated in before they were graphs); batch boundaries depend only on the source's
// parameters, never on the thread count. Not thread-safe (serial next()).
#pragma once
#include <vector>

#include "kernels/grid.hpp"
#include "stream/stage.hpp"

namespace meshless {

inline constexpr std::size_t kQueriesPerBatch = 4096;

class QueryListSource final : public Source {
public:
    Payload gives() const override { return Payload::queries; }
    QueryListSource(std::vector<Vec3> at, bool want_grad, std::size_t batch_queries = kQueriesPerBatch);
    std::optional<Batch> next() override;

private:
    std::vector<Vec3> at_;
    bool want_grad_;
    std::size_t per_, next_ = 0;
    std::uint64_t seq_ = 0;
};

/// A w x h raster of the plane `axis` = at: pixel (row r, column c) is at
///   q[ua] = lo_u + (c + 0.5) * pixel,  q[va] = lo_v + (h - 1 - r + 0.5) * pixel,  q[axis] = at,
/// with (ua, va) the two other axes in increasing order (row 0 is the top, the largest va).
struct PlaneRaster {
    int axis = 2;
    double at = 0;
    double lo_u = 0, lo_v = 0, pixel = 1;
    int width = 2, height = 2;
    Vec3 position(int row, int col) const;
};

class PlaneRasterSource final : public Source {
public:
    Payload gives() const override { return Payload::queries; }
    explicit PlaneRasterSource(const PlaneRaster& r, std::size_t batch_queries = kQueriesPerBatch)
        : r_(r), per_(batch_queries ? batch_queries : 1) {}
    std::optional<Batch> next() override;

private:
    PlaneRaster r_;
    std::size_t per_, next_ = 0;
    std::uint64_t seq_ = 0;
};

class GridRasterSource final : public Source {
public:
    Payload gives() const override { return Payload::queries; }
    explicit GridRasterSource(const GridSpec& g, std::size_t batch_queries = kQueriesPerBatch)
        : g_(g), per_(batch_queries ? batch_queries : 1), end_(g.voxel_count()) {}
    /// The samples [first, end) of the grid only (x fastest; a run of whole z layers, say).
    GridRasterSource(const GridSpec& g, std::int64_t first, std::int64_t end, std::size_t batch_queries = kQueriesPerBatch)
        : g_(g), per_(batch_queries ? batch_queries : 1), next_(first), end_(end) {}
    std::optional<Batch> next() override;

private:
    GridSpec g_;
    std::size_t per_;
    std::int64_t next_ = 0, end_ = 0;
    std::uint64_t seq_ = 0;
};

}  // namespace meshless
