// zlib/gzip decompression: a streaming reader over a file and a one-shot buffer inflater.
//
// Both accept zlib- and gzip-wrapped deflate streams (auto-detected) and concatenated gzip
// members. Units: bytes. Throws IoError (cannot open/read) and FormatError ("PATH: corrupt
// compressed data: ..." or "PATH: compressed data ends after N bytes, expected M").
// Thread-safety: an InflateReader is single-threaded; distinct readers are independent.
// Dissertation: none (input plumbing for chapter 3).
#pragma once
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

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
    /// Discards n decompressed bytes (FormatError if the stream ends first).
    void skip(std::uint64_t n);
    /// Decompressed bytes delivered so far.
    std::uint64_t position() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

/// Inflates a whole zlib/gzip buffer whose decompressed size is exactly `expected` bytes.
/// `path` is only used in messages.
std::vector<std::byte> inflate_exact(const std::byte* data, std::size_t n, std::size_t expected, const std::string& path);
/// Inflates into dst (exactly `expected` bytes).
void inflate_into(const std::byte* data, std::size_t n, std::byte* dst, std::size_t expected, const std::string& path);

/// True when the bytes start with the gzip magic 1f 8b.
bool is_gzip_magic(const void* data, std::size_t n);

}  // namespace meshless
