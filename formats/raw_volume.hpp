// Headerless raw volumes. Layout comes from, in increasing priority: the file name convention
// `name_XxYxZ_type.raw` (e.g. neghip_64x64x64_uint8.raw; type uint8|int8|uint16|int16|uint32|
// int32|float32|float64), a Voreen `.dat` in the same directory (same stem, or any .dat whose
// ObjectFileName names this file), and RawOptions (dims, type, big_endian, spacing).
// The file must hold exactly X*Y*Z*size bytes.
// Throws IoError (cannot open / directory), FormatError ("PATH: expected N bytes for 64x64x64
// uint8, file has M"; missing layout), InvalidArgument (RawOptions dims < 1 or spacing <= 0).
// Thread-safety: reentrant. Dissertation: chapter 3 input.
#pragma once
#include <array>
#include <optional>
#include <string>

#include "formats/payload.hpp"

namespace meshless {

struct RawNameLayout {
    std::array<std::int64_t, 3> dims;
    StoredType type;
};
/// Parses `name_XxYxZ_type.raw` (also .bin/.dat-less); nullopt if the name does not follow it.
std::optional<RawNameLayout> parse_raw_name(const std::string& path);

PayloadPlan plan_raw(const std::string& path, const RawOptions& opts);
VolumeInfo probe_raw(const std::string& path, const RawOptions& opts);
Volume read_raw(const std::string& path, const RawOptions& opts);

}  // namespace meshless
