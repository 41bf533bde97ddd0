#include "kernels/grid.hpp"

#include "kernels/significant_text.hpp"
#include "kernels/checked_size.hpp"
#include "kernels/errors.hpp"

#include <cassert>
#include <cstdio>
#include <cmath>
#include <limits>
#include <string>
#include <type_traits>
#include <algorithm>

namespace meshless {

std::size_t sample_size(SampleType t) {
    switch (t) {
        case SampleType::u8: return 1;
        case SampleType::i16:
        case SampleType::u16: return 2;
        case SampleType::f32: return 4;
    }
    return 0;
}

const char* to_string(SampleType t) {
    switch (t) {
        case SampleType::u8: return "uint8";
        case SampleType::i16: return "int16";
        case SampleType::u16: return "uint16";
        case SampleType::f32: return "float32";
    }
    return "?";
}

std::optional<SampleType> parse_sample_type(std::string_view s) {
    std::string l(s);
    for (auto& c : l) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (l == "uint8" || l == "uchar" || l == "unsigned char" || l == "uint8_t" || l == "u8" ||
        l == "met_uchar" || l == "unsigned_char")
        return SampleType::u8;
    if (l == "int16" || l == "short" || l == "int16_t" || l == "i16" || l == "met_short" ||
        l == "signed short" || l == "short int" || l == "signed short int")
        return SampleType::i16;
    if (l == "uint16" || l == "ushort" || l == "unsigned short" || l == "uint16_t" || l == "u16" ||
        l == "met_ushort" || l == "unsigned_short" || l == "unsigned short int")
        return SampleType::u16;
    if (l == "float32" || l == "float" || l == "f32" || l == "met_float")
        return SampleType::f32;
    return std::nullopt;
}

std::int64_t GridSpec::voxel_count() const {
    if (dims[0] < 1 || dims[1] < 1 || dims[2] < 1) return 0;  // an empty grid (the default one)
    return static_cast<std::int64_t>(checked_volume(dims[0], dims[1], dims[2], "grid dims"));
}

std::int64_t GridSpec::cell_count() const {
    if (dims[0] < 2 || dims[1] < 2 || dims[2] < 2) return 0;
    return static_cast<std::int64_t>(checked_volume(dims[0] - 1, dims[1] - 1, dims[2] - 1, "grid cells"));
}

namespace {
std::string number(double v) { return significant_text(v, 6); }
}  // namespace

void validate_grid(const GridSpec& g, std::string_view context) {
    const std::string ctx = std::string(context) + ": dimensions " + std::to_string(g.dims[0]) + "x" +
                            std::to_string(g.dims[1]) + "x" + std::to_string(g.dims[2]);
    checked_volume(g.dims[0], g.dims[1], g.dims[2], ctx);
    static const char* axis[3] = {"x", "y", "z"};
    constexpr double kFloatMax = std::numeric_limits<float>::max(), kFloatMin = std::numeric_limits<float>::min();
    for (int a = 0; a < 3; ++a) {
        const double s = g.spacing[a];
        if (!std::isfinite(s) || !(s > 0))
            throw FormatError(std::string(context) + ": bad spacing along " + axis[a] + " (" + number(s) +
                              "): must be finite and > 0");
        if (s < kFloatMin)  // records hold float32: a smaller spacing gives zero radii and cell sizes
            throw FormatError(std::string(context) + ": bad spacing along " + axis[a] + " (" + number(s) +
                              "): below " + number(kFloatMin) + ", the smallest normal float32 the point records can hold");
        if (!std::isfinite(g.origin[a]))
            throw FormatError(std::string(context) + ": bad origin along " + axis[a] + " (" + number(g.origin[a]) +
                              "): must be finite");
        // every sample's world position must be a finite float32 (PointRecord, SampleRecord)
        const double far = g.origin[a] + static_cast<double>(std::max<std::int64_t>(g.dims[a] - 1, 0)) * s;
        if (!(std::fabs(g.origin[a]) <= kFloatMax) || !(std::fabs(far) <= kFloatMax))
            throw FormatError(std::string(context) + ": origin " + number(g.origin[a]) + " and spacing " + number(s) + " along " +
                              axis[a] + " put samples at " + number(far) + ", beyond the float32 range (" + number(kFloatMax) +
                              ") the point records hold");
    }
}

void validate_given_spacing(const GridSpec& g, std::string_view context) {
    constexpr double kFloatMax = std::numeric_limits<float>::max(), kFloatMin = std::numeric_limits<float>::min();
    const std::string given = "--spacing " + number(g.spacing[0]) + "," + number(g.spacing[1]) + "," + number(g.spacing[2]) + ": " +
                              std::string(context) + ": ";
    static const char* axis[3] = {"x", "y", "z"};
    for (int a = 0; a < 3; ++a) {
        const double s = g.spacing[a];
        if (!std::isfinite(s) || !(s >= kFloatMin))
            throw InvalidArgument(given + "spacing along " + axis[a] + " must be finite and at least " + number(kFloatMin) +
                                  " (the smallest normal float32 the point records hold)");
        if (!std::isfinite(g.origin[a]) || g.dims[a] < 1) continue;  // the file's fault: validate_grid says so
        const double far = g.origin[a] + static_cast<double>(g.dims[a] - 1) * s;
        if (!(std::fabs(far) <= kFloatMax))
            throw InvalidArgument(given + "spacing " + number(s) + " along " + axis[a] + " puts the last of " +
                                  std::to_string(g.dims[a]) + " samples at " + number(far) + ", beyond the float32 range (" +
                                  number(kFloatMax) + ") the point records hold");
    }
    validate_grid(g, context);
}

double VolumeView::at(std::int64_t linear) const {
    assert(linear >= 0 && linear < grid.voxel_count());
    return visit_samples(*this, [&](auto* p) { return static_cast<double>(p[linear]); });
}

double VolumeView::at(std::int64_t i, std::int64_t j, std::int64_t k) const {
    return at(grid.index(i, j, k));
}

Volume::Volume(GridSpec g, SampleType t)
    : grid(g), type(t), bytes(static_cast<std::size_t>(g.voxel_count()) * sample_size(t)) {}

namespace {

template <class T>
std::array<double, 2> range_of(const T* p, std::size_t n) {
    if constexpr (std::is_floating_point_v<T>) {
        // non-finite samples become +inf for the minimum and -inf for the maximum; written as
        // selects and min/max so that the loop vectorises (minps/maxps)
        constexpr T inf = std::numeric_limits<T>::infinity(), big = std::numeric_limits<T>::max();
        T lo = inf, hi = -inf;
        for (std::size_t i = 0; i < n; ++i) {
            const T x = p[i];
            const bool finite = std::fabs(x) <= big;  // false for NaN and +-Inf
            const T xl = finite ? x : inf, xh = finite ? x : -inf;
            lo = xl < lo ? xl : lo;
            hi = xh > hi ? xh : hi;
        }
        if (!(lo <= hi)) return {std::nan(""), std::nan("")};
        return {static_cast<double>(lo), static_cast<double>(hi)};
    } else {
        if (n == 0) return {std::nan(""), std::nan("")};
        T lo = std::numeric_limits<T>::max(), hi = std::numeric_limits<T>::lowest();
        for (std::size_t i = 0; i < n; ++i) {
            const T x = p[i];
            lo = x < lo ? x : lo;
            hi = x > hi ? x : hi;
        }
        return {static_cast<double>(lo), static_cast<double>(hi)};
    }
}

}  // namespace

std::array<double, 2> value_range(const VolumeView& v) {
    const auto n = static_cast<std::size_t>(std::max<std::int64_t>(0, v.grid.voxel_count()));
    if (n == 0 || v.data == nullptr) return {std::nan(""), std::nan("")};
    return visit_samples(v, [&](auto* p) { return range_of(p, n); });
}

std::array<double, 2> Volume::value_range() const { return meshless::value_range(view()); }

}  // namespace meshless
