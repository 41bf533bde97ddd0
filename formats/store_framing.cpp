#include "formats/store_framing.hpp"

#include <cstring>

#include "kernels/errors.hpp"

namespace meshless {

void check_store_preamble(const StoreReadAt& read, std::uint64_t size, const std::string& name, const StoreFraming& f) {
    const std::string what(f.what);
    auto bad = [&](const std::string& msg) { return FormatError(name + ": " + msg); };
    if (size < 8) throw bad("not a meshless " + what + " (file of " + std::to_string(size) + " bytes)");
    unsigned char m[8];
    read(m, 8, 0);
    if (std::memcmp(m, f.magic.data(), 8) != 0) throw bad("not a meshless " + what + " (bad magic)");
    if (size < 12) throw bad("truncated " + what + " (" + std::to_string(size) + " bytes)");
    unsigned char v[4];
    read(v, 4, 8);
    std::uint32_t version = 0;
    std::memcpy(&version, v, 4);
    if (version != f.version)
        throw bad("unsupported " + what + " version " + std::to_string(version) + " (this build reads version " +
                  std::to_string(f.version) + std::string(f.version_hint) + ")");
    if (size < f.header_bytes + kStoreFooterBytes)
        throw bad("truncated " + what + " (" + std::to_string(size) + " bytes; header and footer need " +
                  std::to_string(f.header_bytes + kStoreFooterBytes) + ")");
}

std::array<unsigned char, kStoreFooterBytes> encode_store_footer(std::uint64_t index_offset, std::uint64_t entries,
                                                                  std::uint32_t index_crc, std::uint32_t version,
                                                                  std::string_view end_magic) {
    std::array<unsigned char, kStoreFooterBytes> f{};
    put_le<std::uint64_t>(f.data(), index_offset);
    put_le<std::uint64_t>(f.data() + 8, entries);
    put_le<std::uint32_t>(f.data() + 16, index_crc);
    put_le<std::uint32_t>(f.data() + 20, version);
    std::memcpy(f.data() + 24, end_magic.data(), 8);
    return f;
}

}  // namespace meshless
