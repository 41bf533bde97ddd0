#include "formats/point_set_chunks.hpp"

#include <algorithm>
#include <cmath>

#include "formats/point_set_reader.hpp"
#include "formats/point_store.hpp"
#include "formats/points_ply.hpp"

namespace meshless {

namespace {

constexpr std::size_t kChunkPoints = 65536;

}  // namespace

PointChunkTotals stream_point_set(const std::vector<std::string>& paths, const PointSetOptions& o,
                                  const std::function<void(std::span<const double>)>& chunk,
                                  const std::function<void(std::size_t)>& file_done) {
    if (paths.empty()) throw InvalidArgument("no point-set files given");
    PointChunkTotals t;
    auto agree = [&](std::size_t i, const std::string& name, bool has) {
        if (i == 0) {
            t.value_name = name;
            t.has_values = has;
        } else if (name != t.value_name || has != t.has_values) {
            throw FormatError(paths[i] + ": scalar '" + name + "' differs from '" + t.value_name + "' in " + paths[0]);
        }
    };
    auto emit = [&](std::span<const double> xyzv) {
        t.points += xyzv.size() / 4;
        chunk(xyzv);
    };
    std::vector<double> buf;
    for (std::size_t i = 0; i < paths.size(); ++i) {
        const std::string& path = paths[i];
        const std::string f = point_set_format(path);
        if (f == "ply") {
            stream_points_ply(
                path, o, [&](const std::string& name, bool has) { agree(i, name, has); }, emit, t.dropped_nonfinite);
        } else if (f == "point-store") {
            const auto store = PointStore::open(path);
            agree(i, store->info().value_name, store->info().has_values);
            t.dropped_nonfinite += store->info().dropped_nonfinite;
            t.dropped_blanked += store->info().dropped_blanked;
            for (std::size_t b = 0; b < store->bricks().size(); ++b) {
                store->read_brick(b, buf);
                emit(buf);
            }
        } else {
            PointSetOptions each = o;
            each.merge_blocks = false;
            const PointSet ps = read_point_set(path, each);
            agree(i, ps.value_name, ps.has_values);
            t.dropped_nonfinite += ps.dropped_nonfinite;
            t.dropped_blanked += ps.dropped_blanked;
            for (std::size_t k0 = 0; k0 < ps.size(); k0 += kChunkPoints) {
                const std::size_t k1 = std::min(ps.size(), k0 + kChunkPoints);
                buf.clear();
                for (std::size_t k = k0; k < k1; ++k) buf.insert(buf.end(), {ps.pos[k].x, ps.pos[k].y, ps.pos[k].z, ps.value[k]});
                emit(buf);
            }
        }
        if (file_done) file_done(i);
    }
    return t;
}

}  // namespace meshless
