// Sample types as they are stored in files (wider than SampleType) and their conversion into a Volume.
//
// Stored types: u8, i8, u16, i16, u32, i32, u64, i64, f32, f64. The in-memory Volume keeps
// u8/i16/u16/f32 natively; i8 widens to i16; u32/i32/u64/i64/f64 convert to f32 (exact for
// |v| < 2^24; larger integers round, f64 loses precision: documented, not reported).
// Byte order: payload bytes are swapped in place when the file order differs from the host
// (little endian). Thread-safety: pure functions, reentrant. Throws FormatError (size mismatch).
// Dissertation: none (I/O support for chapter 3 inputs).
#pragma once
#include <bit>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "kernels/grid.hpp"

namespace meshless {

enum class StoredType : std::uint8_t { u8, i8, u16, i16, u32, i32, u64, i64, f32, f64 };

std::size_t stored_size(StoredType t);
/// "uint8", "int8", ..., "float32", "float64".
const char* to_string(StoredType t);
/// The Volume sample type a stored type becomes (u8->u8, i8->i16, i16, u16, f32; others -> f32).
SampleType volume_type_for(StoredType t);
/// Accepts uint8/int8/uint16/.../float32/float64 and the C names (uchar, char, signed char, short,
/// ushort, unsigned short, int, uint, unsigned int, float, double, long long, ...); case-insensitive.
/// Returns nullopt when unknown.
std::optional<StoredType> parse_stored_type(std::string_view s);

/// True when this machine is little endian (the only case the Volume layout supports natively).
constexpr bool host_is_little_endian() {
    return std::endian::native == std::endian::little;
}

/// Swaps the bytes of each `elem`-byte element in place (elem 1 is a no-op).
void byte_swap_in_place(std::byte* data, std::size_t n_bytes, std::size_t elem);

/// Turns a stored payload into a Volume: checks the size (FormatError "PATH: expected N bytes for
/// DIMS TYPE, got M"), swaps to host order when `big_endian` says so, converts to the volume type.
/// `payload` is consumed (moved into the Volume when no conversion is needed).
Volume make_volume(SampleBytes&& payload, StoredType t, bool big_endian, const GridSpec& grid,
                   const std::string& path);

/// "64x64x64" for messages.
std::string dims_string(const GridSpec& g);

}  // namespace meshless
