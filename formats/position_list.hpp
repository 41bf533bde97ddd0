// A list of world positions read from a text file or standard input (`meshless probe --at-file`):
// three numbers a line separated by commas, semicolons, tabs or spaces (CSV or whitespace); blank
// lines and # comments skipped; one header line allowed first (a line that does not start with a
// number, "x,y,z"). Further columns are ignored.
// Units: world coordinates, as given. Throws IoError for a directory, a file that cannot be opened or
// a failing read; FormatError "PATH:LINE: expected x,y,z, got '...'" for a line without three
// numbers, "PATH:LINE: non-finite position", "PATH: no positions (...)" when there is none.
// Thread-safety: reentrant (the path "-" reads std::cin). Dissertation chapter 7 (looking at fields).
#pragma once
#include <string>
#include <vector>

#include "kernels/vec3.hpp"

namespace meshless {

/// The positions of `path` ("-": standard input), in order.
std::vector<Vec3> read_positions(const std::string& path);

}  // namespace meshless
