// The framing the meshless stores share (brick stores .mlb, sample stores .mls, point stores
// .mlc; docs/formats.md): an 8-byte magic, a u32 version at byte 8, a header of fixed size, the
// payload, a tail index, and a 32-byte footer: index offset (u64), index entries (u64), index
// CRC-32 (u32), version (u32), an 8-byte end magic. Little-endian (the stores are written and read
// on little-endian machines only).
// Throws FormatError "NAME: ..." (check_store_preamble); the rest does not throw.
// Dissertation: none (the storage of sections 3.5-3.6 and 4.4's data).
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <functional>
#include <string>
#include <string_view>

namespace meshless {

inline constexpr std::size_t kStoreFooterBytes = 32;

/// Writes v's bytes at p (little-endian host, as everywhere in meshless).
template <class T>
void put_le(unsigned char* p, T v) {
    std::memcpy(p, &v, sizeof v);
}
/// The T stored at p by put_le.
template <class T>
T get_le(const unsigned char* p) {
    T v;
    std::memcpy(&v, p, sizeof v);
    return v;
}

/// What a store's first bytes must be, as check_store_preamble checks them.
struct StoreFraming {
    std::string_view what;          ///< the kind in messages: "point store"
    std::string_view magic;         ///< 8 bytes
    std::uint32_t version = 0;      ///< the version this build reads
    std::uint64_t header_bytes = 0;
    std::string_view version_hint;  ///< appended inside the version message's parenthesis ("; remake it with ...")
};

/// Reads exactly n bytes at offset into dst (a FormatError or IoError naming the file otherwise).
using StoreReadAt = std::function<void(void* dst, std::size_t n, std::uint64_t offset)>;

/// Checks, in this order, with one FormatError each: a file of at least 8 bytes ("NAME: not a
/// meshless WHAT (file of N bytes)"), the magic ("... (bad magic)"), room for the version
/// ("NAME: truncated WHAT (N bytes)"), the version ("NAME: unsupported WHAT version V (this build
/// reads version K[hint])") and room for the header and the footer. Reads 12 bytes at most.
void check_store_preamble(const StoreReadAt& read, std::uint64_t size, const std::string& name, const StoreFraming& f);

/// The footer: index_offset, entries, index_crc, version, end_magic (8 bytes).
std::array<unsigned char, kStoreFooterBytes> encode_store_footer(std::uint64_t index_offset, std::uint64_t entries,
                                                                  std::uint32_t index_crc, std::uint32_t version,
                                                                  std::string_view end_magic);

}  // namespace meshless
