// Private file mappings as volume storage: the bytes [offset, offset + count) of a regular file,
// mapped copy-on-write (MAP_PRIVATE, readable and writable: writes copy the page and never reach
// the file) and adopted by a SampleBytes (kernels/sample_bytes.hpp), unmapped when the last
// holder goes. Reading a 69 MB CT this way costs a few milliseconds of page-table work instead of
// zeroing, faulting in and copying 69 MB (about 200 ms on the 2-core test machine).
// Caveat of every mapping: if another process truncates the file while the bytes are alive, reads
// of the lost pages raise SIGBUS. Files replaced by rename (meshless writes all its outputs that
// way) are harmless: the mapping keeps the old inode.
// Throws IoError naming the path (cannot open, not a regular file, mmap failed) and FormatError
// when the range lies outside the file. Thread-safety: reentrant.
#pragma once
#include <cstdint>
#include <string>

#include "kernels/sample_bytes.hpp"

namespace meshless {

/// The file's bytes [offset, offset + count) as adopted SampleBytes (count 0: empty, owned).
SampleBytes map_file_range(const std::string& path, std::uint64_t offset, std::uint64_t count);

}  // namespace meshless
