#include "ooc/verify_point_store.hpp"

#include <algorithm>
#include <vector>

#include "formats/point_store.hpp"
#include "kernels/errors.hpp"

namespace meshless {

PointStoreVerifyReport verify_point_store(const std::string& path,
                                          const std::function<void(std::uint64_t, std::uint64_t)>& progress) {
    PointStoreVerifyReport rep;
    std::unique_ptr<PointStore> store;
    try {
        store = PointStore::open(path);
    } catch (const FormatError& e) {
        rep.message = e.what();
        return rep;
    }
    const PointStoreLayout& layout = store->layout();
    const PointStoreInfo& info = layout.info;
    std::vector<double> pts;
    std::array<double, 3> lo{}, hi{};
    double vmin = 0, vmax = 0;
    for (std::size_t i = 0; i < layout.bricks.size(); ++i) {
        if (progress && i > 0) progress(i, layout.bricks.size());
        try {
            store->read_brick(i, pts);
        } catch (const FormatError& e) {
            rep.first_bad_brick = i;
            rep.message = e.what();
            return rep;
        }
        const std::string why = check_point_brick(layout, i, pts);
        if (!why.empty()) {
            rep.first_bad_brick = i;
            rep.message = path + ": " + point_brick_where(layout, i) + ": " + why;
            return rep;
        }
        const PointBrickEntry& e = layout.bricks[i];
        for (int a = 0; a < 3; ++a) {
            lo[a] = i ? std::min(lo[a], e.lo[a]) : e.lo[a];
            hi[a] = i ? std::max(hi[a], e.hi[a]) : e.hi[a];
        }
        vmin = i ? std::min(vmin, e.vmin) : e.vmin;
        vmax = i ? std::max(vmax, e.vmax) : e.vmax;
        ++rep.bricks_checked;
        rep.points_checked += e.count;
    }
    if (lo != info.lo || hi != info.hi) {
        rep.message = path + ": header bounds differ from the bricks'";
        return rep;
    }
    if (vmin != info.value_min || vmax != info.value_max) {
        rep.message = path + ": header value range differs from the bricks'";
        return rep;
    }
    rep.ok = true;
    rep.message = "ok: " + std::to_string(rep.points_checked) + " points in " + std::to_string(rep.bricks_checked) + " bricks";
    return rep;
}

}  // namespace meshless
