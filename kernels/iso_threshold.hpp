// "Above the isovalue" in a volume's native sample type, so classification compares samples
// without converting them to double: for a sample v of type T, (double)v >= iso  <=>  v >= t.
// Integer types: t = ceil(iso) (clamped to T's range; `none_above` / `all_above` when iso lies
// beyond it). float32: t = the smallest float >= iso. NaN samples compare false (read as below).
// Used by cell classification in kernels/cell_sampling.cpp (dissertation section 3.4).
#pragma once
#include <cmath>
#include <limits>
#include <type_traits>

#include "kernels/grid.hpp"

namespace meshless {

template <class T>
struct IsoThreshold {
    T t{};
    bool none_above = false;  ///< no sample can be >= iso
    bool all_above = false;   ///< every (finite) sample is >= iso

    explicit IsoThreshold(double iso) {
        if constexpr (std::is_floating_point_v<T>) {
            float f = static_cast<float>(iso);
            if (std::isinf(f) && std::isfinite(iso)) f = std::numeric_limits<float>::max();
            if (static_cast<double>(f) < iso) f = std::nextafter(f, std::numeric_limits<float>::infinity());
            t = f;
        } else {
            const double c = std::ceil(iso);
            if (c > static_cast<double>(std::numeric_limits<T>::max())) none_above = true;
            else if (c <= static_cast<double>(std::numeric_limits<T>::min())) all_above = true;
            else t = static_cast<T>(c);
        }
    }
    bool above(T v) const { return v >= t; }
};

/// The isovalue as the active-cell test sees it, for a volume of sample type t, in double: a cell
/// is active for iso exactly when vmin < active_threshold(t, iso) <= vmax, which is the
/// classification of kernels/cell_sampling.hpp (some corner >= iso, some corner < iso, compared in
/// the native type). Integers: ceil(iso); float32: the smallest float >= iso (IsoThreshold<float>).
/// Used by the span-space index of paradigm (A) (ooc/span_space_levels.hpp, ooc/sample_store.cpp).
inline double active_threshold(SampleType t, double iso) {
    if (t == SampleType::f32) return static_cast<double>(IsoThreshold<float>(iso).t);
    return std::ceil(iso);
}

}  // namespace meshless
