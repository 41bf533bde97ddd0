// Point stores (.mlc, formats/point_store_format.hpp) from the command line:
//   meshless convert POINTS... -o pts.mlc [--memory BYTES] [--brick-points B] [--zstd-level N] [--threads N]
//   (meshless verify pts.mlc: stream/store_verification.hpp, as every store)
// `convert` picks this when its -o/--output names a .mlc; `convert VOLUME -o vol.mlb` is unchanged.
// Errors as every command: UsageError/InvalidArgument exit 1 (a --memory too small for one brick),
// FormatError/IoError exit 2.
#pragma once

namespace meshless::cli {

/// True when the command line's -o/--output value ends in ".mlc" (any case).
bool point_store_output_requested(int argc, char** argv);
/// `meshless convert POINTS... -o pts.mlc`.
int cmd_convert_points(int argc, char** argv);

}  // namespace meshless::cli
