#include "ooc/verify_brick_store.hpp"

#include <cmath>
#include <limits>
#include <vector>

#include "kernels/errors.hpp"
#include "ooc/brick_store.hpp"

namespace meshless {

namespace {

bool same(double a, double b) { return (std::isnan(a) && std::isnan(b)) || a == b; }

std::array<double, 2> finite_range(const VolumeView& v) {
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    const std::int64_t n = v.grid.voxel_count();
    visit_samples(v, [&](const auto* p) {
        using T = std::remove_const_t<std::remove_pointer_t<decltype(p)>>;
        if (n == 0) return;
        T tlo = std::numeric_limits<T>::max(), thi = std::numeric_limits<T>::lowest();
        bool any = false;
        for (std::int64_t i = 0; i < n; ++i) {
            const T x = p[i];
            if constexpr (std::is_floating_point_v<T>)
                if (!std::isfinite(x)) continue;
            any = true;
            tlo = std::min(tlo, x);
            thi = std::max(thi, x);
        }
        if (any) {
            lo = static_cast<double>(tlo);
            hi = static_cast<double>(thi);
        }
    });
    if (lo > hi) return {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::quiet_NaN()};
    return {lo, hi};
}

}  // namespace

VerifyReport verify_brick_store(const std::string& path, std::uint64_t budget_bytes,
                                const std::function<void(std::uint64_t, std::uint64_t)>& progress) {
    VerifyReport rep;
    std::unique_ptr<BrickStore> store;
    try {
        store = BrickStore::open(path);
    } catch (const FormatError& e) {
        rep.message = e.what();
        return rep;
    }
    const auto& bricks = store->bricks();
    const auto& info = store->info();
    if (store->max_brick_bytes() > budget_bytes) {
        rep.message = path + ": its bricks take up to " + std::to_string(store->max_brick_bytes()) +
                      " bytes decompressed, more than the memory budget of " + std::to_string(budget_bytes) +
                      " bytes (--memory); not checked";
        rep.over_budget = true;
        return rep;
    }
    std::vector<std::byte> buf;
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (std::size_t i = 0; i < bricks.size(); ++i) {
        if (progress && i > 0) progress(i, bricks.size());
        try {
            store->read_brick(i, buf);
        } catch (const FormatError& e) {
            rep.first_bad_brick = i;
            rep.message = e.what();
            return rep;
        }
        const VolumeView v{buf.data(), info.type, store->brick_grid(i)};
        const auto r = finite_range(v);
        if (!same(r[0], bricks[i].vmin) || !same(r[1], bricks[i].vmax)) {
            rep.first_bad_brick = i;
            rep.message = path + ": brick " + std::to_string(i) + " (voxels " + voxel_range_string(store->box(i)) +
                          "): value range differs from the index";
            return rep;
        }
        if (!std::isnan(r[0])) {
            lo = std::min(lo, r[0]);
            hi = std::max(hi, r[1]);
        }
        ++rep.bricks_checked;
    }
    if (lo > hi) lo = hi = 0;
    if (lo != info.value_min || hi != info.value_max) {
        rep.message = path + ": header value range differs from the bricks' (" + std::to_string(lo) + ".." +
                      std::to_string(hi) + ")";
        return rep;
    }
    rep.ok = true;
    rep.message = "ok: " + std::to_string(rep.bricks_checked) + " bricks";
    return rep;
}

}  // namespace meshless
