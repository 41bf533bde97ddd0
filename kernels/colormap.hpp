// Colour maps for slices of scalar fields (meshless slice) and coloured splats (meshless splat
// --color value): value in [lo, hi] -> RGB8.
// "viridis": matplotlib's perceptually uniform sequential map (van der Walt & Smith 2015), sampled
// at 9 control points (#440154 ... #fde725) and interpolated linearly in RGB; "coolwarm":
// Moreland's diverging cool-to-warm map (ParaView's default), 9 control points likewise; "gray":
// black to white. Values outside [lo, hi] clamp; hi <= lo maps everything to the middle; NaN maps
// to the `nan` colour.
// categorical_color: a qualitative palette for ids (block ids of multiblock points): the 10
// colours of Tableau 10 (matplotlib's "tab10"), id modulo 10.
// Pure, constexpr tables, thread-safe.
#pragma once
#include <array>
#include <cstdint>
#include <string_view>

namespace meshless {

enum class Colormap { coolwarm, gray, viridis };

/// "viridis" | "coolwarm" | "gray"; nullopt-like: returns false when unknown.
bool parse_colormap(std::string_view s, Colormap& out);

std::array<std::uint8_t, 3> map_color(Colormap m, double v, double lo, double hi,
                                      std::array<std::uint8_t, 3> nan = {128, 128, 128});

inline constexpr int kCategoricalColors = 10;
std::array<std::uint8_t, 3> categorical_color(std::uint32_t id);

}  // namespace meshless
