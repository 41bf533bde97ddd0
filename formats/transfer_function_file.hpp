// Transfer-function files for `meshless render --tf FILE` (dissertation section 6.6: volume
// rendering of LOD fields). Plain text, one control point per row:
//     value r g b a
// separated by spaces, tabs or commas; '#' starts a comment; blank lines are ignored. value: the
// data's units, finite; r g b a: numbers in [0, 1] (a is the opacity per reference step, see
// kernels/transfer_function.hpp). Rows must be sorted by value (non-decreasing: equal values make a
// step). At most 65536 rows, 4096 bytes per line.
// Throws FormatError "PATH:LINE: ..." for a malformed, unsorted or out-of-range row, an empty file
// or too many rows; IoError when the file cannot be opened or is a directory.
// Thread-safety: reentrant.
#pragma once
#include <string>
#include <string_view>

#include "kernels/transfer_function.hpp"

namespace meshless {

TransferFunction read_transfer_function_file(const std::string& path);
/// The same from text already in memory (`name` for messages).
TransferFunction parse_transfer_function(std::string_view text, const std::string& name);

}  // namespace meshless
