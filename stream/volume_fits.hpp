// The memory check of a volume read whole: refuses, before anything is read, a volume whose
// decoded samples exceed the budget (the front ends' --memory, else available_memory(),
// stream/available_memory.hpp). Sizes in bytes.
// Throws IoError (check_volume_fits); byte_size_text never throws. Thread-safety: reentrant.
#pragma once
#include <cstdint>
#include <optional>
#include <string>

#include "formats/volume_reader.hpp"

namespace meshless {

/// IoError naming `path`, the decoded size, dims and type, and the budget (`memory`: the --memory the
/// user gave, named so; nullopt: available_memory(), described as what this process may use), and
/// suggesting `meshless convert` to a brick store (which streams). A volume that `map` lets map_volume
/// map costs no memory of its own and always fits.
void check_volume_fits(const std::string& path, const VolumeInfo& vi, bool map, std::optional<std::uint64_t> memory);
/// "1.5 GiB" (binary units; "512 bytes" below 1 KiB).
std::string byte_size_text(std::uint64_t bytes);

}  // namespace meshless
