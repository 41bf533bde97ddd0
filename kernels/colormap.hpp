// Colour maps for slices of scalar fields (meshless slice): value in [lo, hi] -> RGB8.
// "coolwarm": Moreland's diverging cool-to-warm map (ParaView's default), sampled at 9 control
// points and interpolated linearly in RGB; "gray": black to white. Values outside [lo, hi] clamp;
// NaN maps to the `nan` colour. Pure, constexpr tables.
#pragma once
#include <array>
#include <cstdint>
#include <string_view>

namespace meshless {

enum class Colormap { coolwarm, gray };

/// "coolwarm" | "gray"; nullopt-like: returns false when unknown.
bool parse_colormap(std::string_view s, Colormap& out);

std::array<std::uint8_t, 3> map_color(Colormap m, double v, double lo, double hi,
                                      std::array<std::uint8_t, 3> nan = {128, 128, 128});

}  // namespace meshless
