// Command-line options of the commands that read scattered/multiblock point sets (info, probe,
// slice, resample, ...): --columns --value --q --q-component --function --allow-trailing --strict
// --merge-blocks (and --endian, declared by add_volume_options or here). See
// formats/point_set_options.hpp for their meaning. Throws UsageError on malformed values.
#pragma once
#include "cli/args.hpp"
#include "formats/point_set_options.hpp"

namespace meshless::cli {

/// with_endian: also declare --endian little|big (leave false when add_volume_options declared it).
void add_point_set_options(Args& a, bool with_endian);
/// The options given; --endian absent = detect.
PointSetOptions point_set_options(const Args& a);
/// A level of detail's point count (--lod-count, lod --count): an integer >= 1, else UsageError.
std::uint64_t lod_count_arg(const std::string& v, const std::string& option);

}  // namespace meshless::cli
