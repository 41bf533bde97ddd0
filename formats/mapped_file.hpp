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

/// Copies up to n bytes of the regular file open as fd, from byte `offset`, to dst through a
/// transient read-only mapping (unmapped before it returns, so the process's resident memory does
/// not grow with the file): on the 2-core test VM 305 MB took 0.07 s this way and 0.23 s by read(2),
/// whose copy out of the page cache is the slow part. Bulk readers of big files use it (the PLY
/// reader's vertex records). Returns the bytes copied: fewer than n when the file ends first (0 at
/// or past its end). The file position of fd is not used nor moved. Errors: returns 0 and sets
/// errno when the file cannot be stat'ed or mapped (the caller falls back to read(2)). The
/// mapping caveat above applies while it copies.
std::size_t copy_file_bytes(int fd, std::uint64_t offset, std::byte* dst, std::size_t n);

}  // namespace meshless
