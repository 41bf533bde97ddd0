#include "formats/stored_type.hpp"

#include <algorithm>
#include <cstring>

#include "kernels/errors.hpp"

namespace meshless {

std::size_t stored_size(StoredType t) {
    switch (t) {
        case StoredType::u8:
        case StoredType::i8: return 1;
        case StoredType::u16:
        case StoredType::i16: return 2;
        case StoredType::u32:
        case StoredType::i32:
        case StoredType::f32: return 4;
        case StoredType::u64:
        case StoredType::i64:
        case StoredType::f64: return 8;
    }
    return 0;
}

const char* to_string(StoredType t) {
    switch (t) {
        case StoredType::u8: return "uint8";
        case StoredType::i8: return "int8";
        case StoredType::u16: return "uint16";
        case StoredType::i16: return "int16";
        case StoredType::u32: return "uint32";
        case StoredType::i32: return "int32";
        case StoredType::u64: return "uint64";
        case StoredType::i64: return "int64";
        case StoredType::f32: return "float32";
        case StoredType::f64: return "float64";
    }
    return "?";
}

SampleType volume_type_for(StoredType t) {
    switch (t) {
        case StoredType::u8: return SampleType::u8;
        case StoredType::i8:
        case StoredType::i16: return SampleType::i16;
        case StoredType::u16: return SampleType::u16;
        default: return SampleType::f32;
    }
}

std::optional<StoredType> parse_stored_type(std::string_view s) {
    std::string l;
    for (char c : s) {
        if (c == '_') c = ' ';
        l += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    }
    // collapse "  " and trim
    std::string n;
    for (char c : l) {
        if (c == ' ' && (n.empty() || n.back() == ' ')) continue;
        n += c;
    }
    while (!n.empty() && n.back() == ' ') n.pop_back();
    if (n.rfind("met ", 0) == 0) n = n.substr(4);
    struct Alias { const char* name; StoredType t; };
    static constexpr Alias table[] = {
        {"uint8", StoredType::u8}, {"uchar", StoredType::u8}, {"unsigned char", StoredType::u8},
        {"uint8 t", StoredType::u8}, {"u8", StoredType::u8}, {"byte", StoredType::u8},
        {"int8", StoredType::i8}, {"char", StoredType::i8}, {"signed char", StoredType::i8},
        {"int8 t", StoredType::i8}, {"i8", StoredType::i8},
        {"uint16", StoredType::u16}, {"ushort", StoredType::u16}, {"unsigned short", StoredType::u16},
        {"unsigned short int", StoredType::u16}, {"uint16 t", StoredType::u16}, {"u16", StoredType::u16},
        {"int16", StoredType::i16}, {"short", StoredType::i16}, {"short int", StoredType::i16},
        {"signed short", StoredType::i16}, {"signed short int", StoredType::i16}, {"int16 t", StoredType::i16},
        {"i16", StoredType::i16},
        {"uint32", StoredType::u32}, {"uint", StoredType::u32}, {"unsigned int", StoredType::u32},
        {"unsigned", StoredType::u32}, {"uint32 t", StoredType::u32}, {"u32", StoredType::u32},
        {"int32", StoredType::i32}, {"int", StoredType::i32}, {"signed int", StoredType::i32},
        {"signed", StoredType::i32}, {"int32 t", StoredType::i32}, {"i32", StoredType::i32},
        {"uint64", StoredType::u64}, {"ulonglong", StoredType::u64}, {"unsigned long long", StoredType::u64},
        {"unsigned long long int", StoredType::u64}, {"uint64 t", StoredType::u64}, {"u64", StoredType::u64},
        {"int64", StoredType::i64}, {"longlong", StoredType::i64}, {"long long", StoredType::i64},
        {"long long int", StoredType::i64}, {"signed long long", StoredType::i64},
        {"signed long long int", StoredType::i64}, {"int64 t", StoredType::i64}, {"i64", StoredType::i64},
        {"float32", StoredType::f32}, {"float", StoredType::f32}, {"f32", StoredType::f32},
        {"float64", StoredType::f64}, {"double", StoredType::f64}, {"f64", StoredType::f64},
    };
    for (const auto& a : table)
        if (n == a.name) return a.t;
    return std::nullopt;
}

void byte_swap_in_place(std::byte* data, std::size_t n_bytes, std::size_t elem) {
    const std::size_t n = n_bytes / elem;
    switch (elem) {
        case 1: return;
        case 2: {
            for (std::size_t i = 0; i < n; ++i) {
                std::uint16_t v;
                std::memcpy(&v, data + 2 * i, 2);
                v = static_cast<std::uint16_t>((v >> 8) | (v << 8));
                std::memcpy(data + 2 * i, &v, 2);
            }
            return;
        }
        case 4: {
            for (std::size_t i = 0; i < n; ++i) {
                std::uint32_t v;
                std::memcpy(&v, data + 4 * i, 4);
                v = __builtin_bswap32(v);
                std::memcpy(data + 4 * i, &v, 4);
            }
            return;
        }
        case 8: {
            for (std::size_t i = 0; i < n; ++i) {
                std::uint64_t v;
                std::memcpy(&v, data + 8 * i, 8);
                v = __builtin_bswap64(v);
                std::memcpy(data + 8 * i, &v, 8);
            }
            return;
        }
        default:
            for (std::size_t i = 0; i < n; ++i) std::reverse(data + elem * i, data + elem * (i + 1));
    }
}

std::string dims_string(const GridSpec& g) {
    return std::to_string(g.dims[0]) + "x" + std::to_string(g.dims[1]) + "x" + std::to_string(g.dims[2]);
}

namespace {
template <class Src, class Dst>
void convert(const std::byte* in, std::byte* out, std::size_t n) {
    for (std::size_t i = 0; i < n; ++i) {
        Src s;
        std::memcpy(&s, in + i * sizeof(Src), sizeof(Src));
        const Dst d = static_cast<Dst>(s);
        std::memcpy(out + i * sizeof(Dst), &d, sizeof(Dst));
    }
}
}  // namespace

Volume make_volume(SampleBytes&& payload, StoredType t, bool big_endian, const GridSpec& grid,
                   const std::string& path) {
    for (int a = 0; a < 3; ++a)
        if (grid.dims[a] < 1)
            throw FormatError(path + ": invalid dimensions " + dims_string(grid));
    const std::size_t n = static_cast<std::size_t>(grid.voxel_count());
    const std::size_t need = n * stored_size(t);
    if (payload.size() != need)
        throw FormatError(path + ": expected " + std::to_string(need) + " bytes for " + dims_string(grid) + " " +
                          to_string(t) + ", got " + std::to_string(payload.size()));
    if (big_endian == host_is_little_endian()) byte_swap_in_place(payload.data(), payload.size(), stored_size(t));
    Volume v;
    v.grid = grid;
    v.type = volume_type_for(t);
    const bool native = t == StoredType::u8 || t == StoredType::u16 || t == StoredType::i16 || t == StoredType::f32;
    if (native || stored_size(t) == sample_size(v.type)) {
        v.bytes = std::move(payload);  // same size: converted in place below when not native
    } else {
        v.bytes.resize(n * sample_size(v.type));
    }
    if (native) return v;
    std::byte* out = v.bytes.data();
    const std::byte* in = stored_size(t) == sample_size(v.type) ? v.bytes.data() : payload.data();
    switch (t) {
        case StoredType::i8: convert<std::int8_t, std::int16_t>(in, out, n); break;
        case StoredType::u32: convert<std::uint32_t, float>(in, out, n); break;
        case StoredType::i32: convert<std::int32_t, float>(in, out, n); break;
        case StoredType::u64: convert<std::uint64_t, float>(in, out, n); break;
        case StoredType::i64: convert<std::int64_t, float>(in, out, n); break;
        case StoredType::f64: convert<double, float>(in, out, n); break;
        default: break;  // same size: handled above
    }
    return v;
}

}  // namespace meshless
