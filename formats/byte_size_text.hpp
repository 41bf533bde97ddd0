// Byte counts as people read them in messages: "1.5 GiB" (binary units), "512 bytes" below 1 KiB.
// Pure string work; throws nothing but std::bad_alloc.
#pragma once
#include <cstdint>
#include <string>

namespace meshless {

/// "1.5 GiB" (binary units, one decimal; "512 bytes" below 1 KiB).
std::string byte_size_text(std::uint64_t bytes);

}  // namespace meshless
