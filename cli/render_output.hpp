// What --color asks for (cli/common.hpp color_choice; the settings themselves are
// stream/render_settings.hpp), and the file names
// of a turntable's frames (section 3.6: N frames, 360/N degrees apart about the y axis, written as
// NAME_000.png ...; stream/turntable.hpp draws them).
#pragma once
#include <string>

#include "stream/render_settings.hpp"

namespace meshless::cli {

/// What --color asked for, before it is resolved against the input ("auto": value when the points'
/// values vary and the input is not an isosurface, else none).
enum class ColorRequest { automatic, value, block, normal, none };

/// Frame i of a turntable goes to frame_path(path, i): "img.png" -> "img_007.png".
std::string frame_path(const std::string& path, int i);

}  // namespace meshless::cli
