#include "formats/crc32.hpp"

#include <libdeflate.h>

namespace meshless {

std::uint32_t crc32_ieee(std::uint32_t crc, const void* data, std::size_t n) { return libdeflate_crc32(crc, data, n); }

}  // namespace meshless
