#include "kernels/transfer_function.hpp"

#include <algorithm>
#include <cmath>

#include "kernels/errors.hpp"

namespace meshless {

namespace {

bool unit(double x) { return x >= 0.0 && x <= 1.0; }

std::string point_name(std::size_t i) { return "transfer function point " + std::to_string(i + 1); }

}  // namespace

TransferFunction::TransferFunction(std::vector<TransferPoint> points) : points_(std::move(points)) {
    if (points_.empty()) throw InvalidArgument("transfer function: no control points");
    for (std::size_t i = 0; i < points_.size(); ++i) {
        const TransferPoint& p = points_[i];
        if (!std::isfinite(p.value)) throw InvalidArgument(point_name(i) + ": value is not finite");
        if (!unit(p.r) || !unit(p.g) || !unit(p.b) || !unit(p.a))
            throw InvalidArgument(point_name(i) + ": r, g, b, a must lie in [0, 1]");
        if (i > 0 && p.value < points_[i - 1].value)
            throw InvalidArgument(point_name(i) + ": values must be sorted (non-decreasing)");
    }
}

std::array<double, 4> TransferFunction::at(double v) const {
    if (std::isnan(v)) return {0, 0, 0, 0};
    const auto& P = points_;
    auto pack = [](const TransferPoint& p) { return std::array<double, 4>{p.r, p.g, p.b, p.a}; };
    if (v < P.front().value) return pack(P.front());
    if (v >= P.back().value) return pack(P.back());
    // first point with value > v: the segment [it - 1, it] holds v (a step at v takes its right side)
    const auto it = std::upper_bound(P.begin(), P.end(), v, [](double x, const TransferPoint& p) { return x < p.value; });
    const TransferPoint& b = *it;
    const TransferPoint& a = *(it - 1);
    const double t = (v - a.value) / (b.value - a.value);  // b.value > v >= a.value
    return {a.r + t * (b.r - a.r), a.g + t * (b.g - a.g), a.b + t * (b.b - a.b), a.a + t * (b.a - a.a)};
}

double TransferFunction::max_opacity(double lo, double hi) const {
    if (std::isnan(lo) || std::isnan(hi)) return 1.0;  // unknown: never skip
    if (lo > hi) return 0.0;                             // empty: no value at all (no finite sample)
    double m = std::max(at(lo)[3], at(hi)[3]);
    for (const TransferPoint& p : points_)
        if (p.value >= lo && p.value <= hi) m = std::max(m, p.a);
    return m;
}

std::vector<std::string_view> transfer_function_preset_names() { return {"grey", "viridis", "ct-bone", "ct-skin"}; }

bool is_transfer_function_preset(std::string_view name) {
    for (auto n : transfer_function_preset_names())
        if (n == name) return true;
    return name == "gray";
}

TransferFunction transfer_function_preset(std::string_view name, double lo, double hi) {
    if (!(std::isfinite(lo) && std::isfinite(hi) && lo < hi))
        throw InvalidArgument("transfer function preset '" + std::string(name) + "': value range [" + std::to_string(lo) + ", " +
                              std::to_string(hi) + "] is empty or not finite");
    struct Row {
        double t, r, g, b, a;
    };
    std::vector<Row> rows;
    if (name == "grey" || name == "gray") {
        rows = {{0, 0, 0, 0, 0}, {1, 1, 1, 1, 0.5}};
    } else if (name == "viridis") {
        // matplotlib viridis at t = 0, 1/8, ..., 1 (the colour map of kernels/colormap.cpp)
        constexpr double v[9][3] = {{68, 1, 84},    {71, 45, 123},  {59, 82, 139},  {44, 114, 142}, {33, 145, 140},
                                    {40, 174, 128}, {94, 201, 98},  {173, 220, 48}, {253, 231, 37}};
        for (int i = 0; i < 9; ++i) rows.push_back({i / 8.0, v[i][0] / 255, v[i][1] / 255, v[i][2] / 255, 0.5 * i / 8.0});
    } else if (name == "ct-bone") {
        rows = {{0, 0, 0, 0, 0}, {0.55, 0.9, 0.85, 0.75, 0}, {0.7, 1, 0.98, 0.92, 0.9}, {1, 1, 1, 1, 1}};
    } else if (name == "ct-skin") {
        rows = {{0, 0, 0, 0, 0},          {0.25, 0.75, 0.45, 0.35, 0},   {0.32, 0.9, 0.6, 0.5, 0.08},
                {0.45, 0.9, 0.65, 0.55, 0.08}, {0.52, 0.9, 0.7, 0.6, 0},   {0.6, 0.95, 0.93, 0.88, 0},
                {0.75, 1, 0.98, 0.95, 0.8}, {1, 1, 1, 1, 1}};
    } else {
        std::string names;
        for (auto n : transfer_function_preset_names()) names += (names.empty() ? "" : ", ") + std::string(n);
        throw InvalidArgument("unknown transfer function preset '" + std::string(name) + "' (presets: " + names +
                              "; or a file of 'value r g b a' rows)");
    }
    std::vector<TransferPoint> pts;
    for (const Row& r : rows) pts.push_back({lo + r.t * (hi - lo), r.r, r.g, r.b, r.a});
    return TransferFunction(std::move(pts));
}

}  // namespace meshless
