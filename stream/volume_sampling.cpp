#include "stream/volume_sampling.hpp"

#include <algorithm>
#include <array>
#include <optional>
#include <cmath>
#include <vector>

#include "formats/point_set_writer.hpp"
#include "kernels/errors.hpp"
#include "kernels/splitmix.hpp"
#include "kernels/trilinear_field.hpp"
#include "ooc/brick_cache.hpp"
#include "ooc/brick_field.hpp"
#include "ooc/brick_store_values.hpp"

namespace meshless {

std::uint64_t sample_volume_chunks(const GridSpec& g, const SampleValues& values, std::uint64_t count, std::uint64_t seed,
                                   const std::string& name, std::size_t chunk,
                                   const std::function<void(std::span<const Vec3>, std::span<const double>)>& emit) {
    std::array<double, 3> lo{}, ext{};
    for (int k = 0; k < 3; ++k) {
        lo[k] = g.origin[k];
        ext[k] = static_cast<double>(g.dims[k] - 1) * g.spacing[k];
    }
    chunk = std::max<std::size_t>(1, chunk);
    SplitMix rng{seed};
    std::vector<Vec3> p, keep_p;
    std::vector<double> val, keep_v;
    const std::uint64_t max_draws = count > (UINT64_MAX - 1000) / 20 ? UINT64_MAX : count * 20 + 1000;
    std::uint64_t draws = 0, kept = 0, redrawn = 0;
    while (kept < count) {
        // every draw is kept unless its value is not finite, and no more are drawn than are still
        // wanted: the points are the first `count` finite draws whatever the chunk
        const std::size_t want = static_cast<std::size_t>(std::min<std::uint64_t>(chunk, count - kept));
        p.resize(want);
        val.resize(want);
        for (auto& q : p) q = Vec3{lo[0] + rng.unit() * ext[0], lo[1] + rng.unit() * ext[1], lo[2] + rng.unit() * ext[2]};
        draws += want;
        values(p, val);
        const std::size_t finite = static_cast<std::size_t>(std::count_if(val.begin(), val.end(), [](double x) { return std::isfinite(x); }));
        redrawn += want - finite;
        kept += finite;
        if (finite == want) {  // (no redraw: the drawn arrays go on as they are)
            emit(p, val);
        } else if (finite > 0) {
            keep_p.clear();
            keep_v.clear();
            for (std::size_t i = 0; i < want; ++i) {
                if (!std::isfinite(val[i])) continue;
                keep_p.push_back(p[i]);
                keep_v.push_back(val[i]);
            }
            emit(keep_p, keep_v);
        }
        if (draws > max_draws)
            throw FormatError(name + ": too many NaN/Inf cells: " + std::to_string(redrawn) + " of " + std::to_string(draws) +
                              " random positions had no finite value");
    }
    return redrawn;
}

VolumeSample sample_volume(const Volume& v, std::uint64_t count, std::uint64_t seed, const std::string& name) {
    const TrilinearField field(v.view());
    VolumeSample out;
    PointSet& ps = out.points;
    ps.value_name = "value";
    ps.pos.reserve(static_cast<std::size_t>(count));
    ps.value.reserve(static_cast<std::size_t>(count));
    out.redrawn = sample_volume_chunks(
        v.grid, [&](std::span<const Vec3> p, std::span<double> val) { field.evaluate(p, val, {}); }, count, seed, name, 4096,
        [&](std::span<const Vec3> p, std::span<const double> val) {
            ps.pos.insert(ps.pos.end(), p.begin(), p.end());
            ps.value.insert(ps.value.end(), val.begin(), val.end());
        });
    ps.blocks = {PointSetBlock{"sample", {static_cast<std::int64_t>(count), 1, 1}, 0, count}};
    return out;
}

std::uint64_t sample_volume_to_file(const SampleInput& in, std::uint64_t count, std::uint64_t seed, const std::string& name,
                                    const std::string& path, const std::vector<std::string>& comments,
                                    const std::function<void(double)>& progress, std::size_t chunk) {
    if (!in.volume == !in.store) throw InvalidArgument("sample_volume_to_file: give a volume or a brick store");
    PointSetWriter out(path, count, true, "value", comments);
    std::optional<TrilinearField> field;
    std::optional<BrickCache> cache;
    std::optional<BrickStoreField> store_field;
    SampleValues values;
    if (in.volume) {
        field.emplace(in.volume->view());
        values = [&](std::span<const Vec3> p, std::span<double> val) { field->evaluate(p, val, {}); };
        if (chunk == 0) chunk = std::size_t{1} << 20;
    } else {
        cache.emplace(*in.store, std::max(in.memory_bytes / 2, in.store->max_brick_bytes()));
        if (chunk == 0)
            chunk = static_cast<std::size_t>(std::clamp<std::uint64_t>(in.memory_bytes / 2 / kSampleChunkBytes, 65536, std::uint64_t{1} << 22));
        store_field.emplace(*in.store, *cache);
        values = [&](std::span<const Vec3> p, std::span<double> val) { brick_store_values(*in.store, *store_field, p, val); };
    }
    const GridSpec& grid = in.volume ? in.volume->grid : in.store->info().grid;
    const std::uint64_t redrawn = sample_volume_chunks(grid, values, count, seed, name, chunk,
                                                       [&](std::span<const Vec3> p, std::span<const double> val) {
                                                           out.append(p, val);
                                                           if (progress) progress(static_cast<double>(p.size()));
                                                       });
    out.commit();
    return redrawn;
}

}  // namespace meshless
