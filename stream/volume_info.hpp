// The descriptions of volumes for stream/file_info.hpp: a volume file read through its header and
// proven payload (formats/volume_reader.hpp prove_volume), a brick store (.mlb, ooc/brick_store.hpp)
// and a paradigm-(A) sample store (.mls, ooc/sample_store.hpp), each as lines on `out`.
// Throws what the readers throw (FormatError, IoError; IoError too for value_range on a volume larger
// than available_memory(), stream/volume_input.hpp check_volume_fits). Thread-safety: reentrant (distinct `out`).
#pragma once
#include <cstdio>
#include <string>

#include "formats/volume_reader.hpp"

namespace meshless {

/// Format, dims, type, spacing, origin, the point arrays of a file holding several (which one is read,
/// which is the default), encoding, the data files opened, patient axes; the payload
/// decoded through a small buffer. value_range: then read whole and its value range printed.
void describe_volume(const std::string& path, const RawOptions& raw, bool value_range, std::FILE* out);
/// Dims, type, spacing, value range, patient axes, bricks, the largest brick, compression.
void describe_brick_store(const std::string& path, std::FILE* out);
/// The brick store it indexes (identity checked), cells, keys and the span-space index.
void describe_sample_store(const std::string& path, std::FILE* out);

}  // namespace meshless
