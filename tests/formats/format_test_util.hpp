// Helpers for the [formats] tests: an analytic integer-valued field stored in any StoredType and
// byte order, gzip/zlib compression, and file writing. The field values are exactly
// representable in every type the reader converts to, so comparisons are exact.
#pragma once
#include <zlib.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "formats/stored_type.hpp"
#include "kernels/grid.hpp"

namespace meshless::test {

/// The oracle: a value depending on i, j, k in the range of type t, exact in float32.
inline double field_value(StoredType t, std::int64_t i, std::int64_t j, std::int64_t k) {
    const double b = static_cast<double>((i * 7 + j * 13 + k * 29) % 200);
    switch (t) {
        case StoredType::u8: return b;
        case StoredType::i8: return b - 100;
        case StoredType::u16: return b * 300;
        case StoredType::i16: return b * 150 - 15000;
        case StoredType::u32:
        case StoredType::u64: return b * 50000;
        case StoredType::i32:
        case StoredType::i64: return b * 50000 - 5000000;
        case StoredType::f32:
        case StoredType::f64: return b * 0.25 - 7.5;
    }
    return 0;
}

template <class T>
inline void put_value(std::vector<std::byte>& out, T v, bool big) {
    std::byte b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
    if (big) std::reverse(b, b + sizeof(T));
    out.insert(out.end(), b, b + sizeof(T));
}

/// Stored bytes of the field on dims, x fastest.
inline std::vector<std::byte> field_bytes(StoredType t, std::array<std::int64_t, 3> d, bool big) {
    std::vector<std::byte> out;
    for (std::int64_t k = 0; k < d[2]; ++k)
        for (std::int64_t j = 0; j < d[1]; ++j)
            for (std::int64_t i = 0; i < d[0]; ++i) {
                const double v = field_value(t, i, j, k);
                switch (t) {
                    case StoredType::u8: put_value(out, static_cast<std::uint8_t>(v), big); break;
                    case StoredType::i8: put_value(out, static_cast<std::int8_t>(v), big); break;
                    case StoredType::u16: put_value(out, static_cast<std::uint16_t>(v), big); break;
                    case StoredType::i16: put_value(out, static_cast<std::int16_t>(v), big); break;
                    case StoredType::u32: put_value(out, static_cast<std::uint32_t>(v), big); break;
                    case StoredType::i32: put_value(out, static_cast<std::int32_t>(v), big); break;
                    case StoredType::u64: put_value(out, static_cast<std::uint64_t>(v), big); break;
                    case StoredType::i64: put_value(out, static_cast<std::int64_t>(v), big); break;
                    case StoredType::f32: put_value(out, static_cast<float>(v), big); break;
                    case StoredType::f64: put_value(out, v, big); break;
                }
            }
    return out;
}

/// The field as whitespace-separated text.
inline std::string field_text(StoredType t, std::array<std::int64_t, 3> d) {
    std::string s;
    for (std::int64_t k = 0; k < d[2]; ++k)
        for (std::int64_t j = 0; j < d[1]; ++j)
            for (std::int64_t i = 0; i < d[0]; ++i) {
                char buf[64];
                std::snprintf(buf, sizeof buf, "%.17g", field_value(t, i, j, k));
                s += buf;
                s += (i + 1 == d[0]) ? '\n' : ' ';
            }
    return s;
}

/// Number of samples differing from the oracle (0 means an exact match).
inline std::int64_t mismatches(const Volume& v, StoredType t) {
    std::int64_t bad = 0;
    const auto view = v.view();
    for (std::int64_t k = 0; k < v.grid.dims[2]; ++k)
        for (std::int64_t j = 0; j < v.grid.dims[1]; ++j)
            for (std::int64_t i = 0; i < v.grid.dims[0]; ++i)
                if (view.at(i, j, k) != field_value(t, i, j, k)) ++bad;
    return bad;
}

/// Deflate with a zlib (window 15) or gzip (window 31) wrapper.
inline std::vector<std::byte> deflate_bytes(const void* data, std::size_t n, bool gzip) {
    z_stream zs{};
    if (deflateInit2(&zs, 6, Z_DEFLATED, gzip ? 31 : 15, 8, Z_DEFAULT_STRATEGY) != Z_OK) throw std::runtime_error("deflateInit2");
    std::vector<std::byte> out(deflateBound(&zs, static_cast<uLong>(n)) + 32);
    zs.next_in = reinterpret_cast<Bytef*>(const_cast<void*>(data));
    zs.avail_in = static_cast<uInt>(n);
    zs.next_out = reinterpret_cast<Bytef*>(out.data());
    zs.avail_out = static_cast<uInt>(out.size());
    if (deflate(&zs, Z_FINISH) != Z_STREAM_END) throw std::runtime_error("deflate");
    out.resize(zs.total_out);
    deflateEnd(&zs);
    return out;
}
inline std::vector<std::byte> deflate_bytes(const std::vector<std::byte>& v, bool gzip) {
    return deflate_bytes(v.data(), v.size(), gzip);
}

inline void write_file(const std::string& path, const std::string& text, const std::vector<std::byte>& bytes = {}) {
    std::ofstream f(path, std::ios::binary);
    f.write(text.data(), static_cast<std::streamsize>(text.size()));
    f.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    if (!f) throw std::runtime_error("cannot write " + path);
}

inline std::vector<std::byte> to_bytes(const std::string& s) {
    std::vector<std::byte> b(s.size());
    std::memcpy(b.data(), s.data(), s.size());
    return b;
}

}  // namespace meshless::test
