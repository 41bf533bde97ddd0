// zlib/gzip decompression: a streaming reader over a file (zlib's inflate, for slab streaming
// and header peeks) and whole-buffer inflaters (libdeflate, about 3x zlib's speed on our data:
// 5.0 vs 14.6 ms for the 8.7 MB vtk.js LIDC2 array; Boost.Iostreams' gzip filter took 25 ms).
//
// All accept zlib- and gzip-wrapped deflate streams (auto-detected) and concatenated gzip
// members. One end-of-stream rule (the gzip tail rule) holds for every path: once a payload's
// expected bytes are complete, the stream or member that delivered the last byte must end there,
// and bytes after it that begin a further gzip member (1f 8b, even a damaged one) are refused
// with gzip_overrun_message; any other trailing bytes are padding and ignored. Units: bytes. Throws IoError (cannot open/read) and FormatError ("PATH: corrupt
// compressed data ...", "PATH: compressed data ends after N decompressed bytes, expected M" or
// "PATH: compressed data decompresses to more than M bytes").
// Thread-safety: an InflateReader is single-threaded; distinct readers are independent.
// Dissertation: none (input plumbing for chapter 3).
#pragma once
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "kernels/sample_bytes.hpp"

namespace meshless {

/// Deflate's largest expansion (zlib technical details: 1032:1). Readers refuse a header whose
/// decompressed size exceeds this many times the compressed bytes before allocating anything.
inline constexpr std::uint64_t kMaxDeflateRatio = 1032;

/// Streams decompressed bytes from a compressed file region starting at `offset`.
class InflateReader {
public:
    InflateReader(const std::string& path, std::uint64_t offset = 0);
    ~InflateReader();
    InflateReader(const InflateReader&) = delete;
    InflateReader& operator=(const InflateReader&) = delete;

    /// Reads up to n bytes; returns fewer only at the end of the compressed data.
    std::size_t read(void* dst, std::size_t n);
    /// Reads exactly n bytes or throws FormatError naming `what`.
    void read_exact(void* dst, std::size_t n, const char* what);
    /// The payload is complete after `expected` decompressed bytes (position()): throws
    /// gzip_overrun_message when the current member decodes to more data or a further gzip
    /// member follows it (the gzip tail rule above); other trailing bytes are accepted.
    void expect_end(std::uint64_t expected);
    /// Discards n decompressed bytes (FormatError if the stream ends first).
    void skip(std::uint64_t n);
    /// Decompressed bytes delivered so far.
    std::uint64_t position() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

/// Inflates a whole zlib/gzip buffer (one zlib stream, or gzip members) whose decompressed size
/// is exactly `expected` bytes into dst. `path` is only used in messages. After the member that
/// completes `expected` bytes, a further gzip member is an error (the gzip tail rule), other
/// bytes are padding; a member that would write more is an error.
void inflate_into(const std::byte* data, std::size_t n, std::byte* dst, std::size_t expected, const std::string& path);

/// The compressed data of file `path` from byte `offset` to its end, inflated whole: exactly
/// skip + n decompressed bytes, of which the n after the first `skip` are returned. The claim is
/// checked first against deflate's largest expansion (kMaxDeflateRatio) over the compressed bytes
/// present (FormatError), and the output is fresh zero pages (SampleBytes::lazy_zeroed) that
/// become resident only as the inflated data is written. The compressed bytes are mapped, not copied.
SampleBytes inflate_file(const std::string& path, std::uint64_t offset, std::uint64_t skip, std::uint64_t n);

/// "PATH: compressed data decompresses to more than N bytes": the one message of the gzip tail rule.
std::string gzip_overrun_message(const std::string& path, std::uint64_t expected);

/// True when the bytes start with the gzip magic 1f 8b.
bool is_gzip_magic(const void* data, std::size_t n);

}  // namespace meshless
