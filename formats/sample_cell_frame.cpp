#include "formats/sample_cell_frame.hpp"

#include <algorithm>
#include <bit>
#include <climits>
#include <cmath>
#include <cstring>
#include <string>
#include <utility>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "kernels/cell_sampling.hpp"
#include "kernels/errors.hpp"

namespace meshless {

namespace {

enum CornerCoding : std::uint8_t { kU8 = 1, kI16 = 2, kU16 = 3, kF32 = 4 };
constexpr std::size_t kExceptionBytes = 4 + sizeof(SampleRecord);
/// Records rebuilt per step of the encoder and decoder: their scratch stays in the L1/L2 caches.
constexpr std::size_t kStep = 256;

std::size_t corner_bytes(std::uint8_t coding) { return coding == kU8 ? 1 : coding == kF32 ? 4 : 2; }

/// Writes the 8 corners in the coding at p; false (p's bytes unspecified) when one is not exactly
/// a value of the coding (a fraction, -0, NaN, Inf, or out of range). float32 always fits.
bool put_corners(const float c[8], std::uint8_t coding, char* p) {
    if (coding == kF32) {
        std::memcpy(p, c, 32);
        return true;
    }
#if defined(__SSE2__)
    if (coding != kU16) {
        const __m128 f0 = _mm_loadu_ps(c), f1 = _mm_loadu_ps(c + 4);
        const __m128i v0 = _mm_cvttps_epi32(f0), v1 = _mm_cvttps_epi32(f1);  // 0x80000000 out of range
        const __m128i exact = _mm_and_si128(_mm_cmpeq_epi32(_mm_castps_si128(_mm_cvtepi32_ps(v0)), _mm_castps_si128(f0)),
                                            _mm_cmpeq_epi32(_mm_castps_si128(_mm_cvtepi32_ps(v1)), _mm_castps_si128(f1)));
        const __m128i w = _mm_packs_epi32(v0, v1);  // int16, saturated
        __m128i back = w;
        if (coding == kU8) {
            const __m128i b8 = _mm_packus_epi16(w, w);  // uint8, saturated
            back = _mm_unpacklo_epi8(b8, _mm_setzero_si128());
            _mm_storel_epi64(reinterpret_cast<__m128i*>(p), b8);
        } else {
            _mm_storeu_si128(reinterpret_cast<__m128i*>(p), w);
        }
        // in range: unsaturated, so widening back gives the same integers
        const __m128i lo = _mm_srai_epi32(_mm_unpacklo_epi16(back, back), 16);
        const __m128i hi = _mm_srai_epi32(_mm_unpackhi_epi16(back, back), 16);
        const __m128i same = _mm_and_si128(exact, _mm_and_si128(_mm_cmpeq_epi32(lo, v0), _mm_cmpeq_epi32(hi, v1)));
        return _mm_movemask_epi8(same) == 0xffff;
    }
#endif
    const float lo = coding == kI16 ? -32768.0f : 0.0f, hi = coding == kU8 ? 255.0f : coding == kI16 ? 32767.0f : 65535.0f;
    for (int q = 0; q < 8; ++q) {
        const float f = c[q];
        if (!(f >= lo && f <= hi)) return false;
        const auto v = static_cast<std::int32_t>(f);
        if (std::bit_cast<std::uint32_t>(static_cast<float>(v)) != std::bit_cast<std::uint32_t>(f)) return false;
        if (coding == kU8) {
            p[q] = static_cast<char>(static_cast<std::uint8_t>(v));
        } else {
            const auto u = static_cast<std::uint16_t>(v);  // int16's two's complement bits
            std::memcpy(p + 2 * q, &u, 2);
        }
    }
    return true;
}

/// The next coding to try after `coding` failed on corners c: up the ladder uint8, int16, uint16,
/// float32 (never down, so a frame is restarted at most three times).
std::uint8_t wider(std::uint8_t coding, const float c[8]) {
    const bool negative = std::any_of(c, c + 8, [](float f) { return f < 0; });
    const bool large = std::any_of(c, c + 8, [](float f) { return f > 32767; });
    if (coding == kU8) return negative || !large ? kI16 : kU16;
    if (coding == kI16 && !negative) return kU16;
    return kF32;
}

template <class T>
void put(char*& p, T v) {
    std::memcpy(p, &v, sizeof v);
    p += sizeof v;
}
template <class T>
T get(const unsigned char*& p) {
    T v;
    std::memcpy(&v, p, sizeof v);
    p += sizeof v;
    return v;
}

}  // namespace

SampleCellEncoder::SampleCellEncoder(const CellGrid& grid, Verify verify) : grid_(grid), verify_(verify) {
    for (int a = 0; a < 3; ++a) inverse_[a] = 1.0 / grid.spacing[a];
}

bool SampleCellEncoder::same_position(const SampleRecord& s, const std::uint32_t* ijk) const {
    // complete_centre_samples' arithmetic for the fields that depend on the cell's indices
    const auto bits = [](float f) { return std::bit_cast<std::uint32_t>(f); };
    bool same = true;
    for (int a = 0; a < 3; ++a) {
        const CellAxis x = cell_axis(grid_.origin[a], grid_.spacing[a], ijk[a]);
        same = same && bits(x.lo) == bits(s.cell_lo[a]) && bits(x.centre) == bits(s.pos[a]) &&
               bits(static_cast<float>(grid_.spacing[a])) == bits(s.cell_size[a]);
    }
    return same;
}

bool SampleCellEncoder::encode(const SampleRecord* rec, std::size_t n, std::vector<char>& out) {
    if (n == 0) return false;
    const float radius = rec[0].radius;
    std::uint32_t ijk[3 * kStep];
    if (verify_ == Verify::all) rebuilt_.resize(std::min(n, kStep));
    // One pass in the coding and index width of the previous frame; a corner or index that does not
    // fit widens them and starts the frame again (a few times per stream at most).
restart:
    const std::size_t cb = corner_bytes(coding_), ib = index_bytes_, slot = 3 * ib + 8 * cb;
    const std::size_t base = kSampleCellHeaderBytes + n * slot;
    if (base > n * sizeof(SampleRecord) / 2) return false;
    out.resize(base);
    exceptions_.clear();
    char* p = out.data() + kSampleCellHeaderBytes;
    for (std::size_t first = 0; first < n; first += kStep) {
        const std::size_t m = std::min(kStep, n - first);
        for (std::size_t r = 0; r < m; ++r) {
            const SampleRecord& s = rec[first + r];
            for (int a = 0; a < 3; ++a) {
                const double d = (static_cast<double>(s.cell_lo[a]) - grid_.origin[a]) * inverse_[a];
                // off the index range: any index will do, the check below makes it an exception
                ijk[3 * r + a] = d >= -0.5 && d < 4294967295.0 ? static_cast<std::uint32_t>(d + 0.5) : 0;
            }
            if (verify_ == Verify::all) std::memcpy(&rebuilt_[r], &s, sizeof s);
        }
        if (verify_ == Verify::all) complete_centre_samples(grid_.origin, grid_.spacing, ijk, rebuilt_.data(), m);
        for (std::size_t r = 0; r < m; ++r, p += slot) {
            const SampleRecord& s = rec[first + r];
            const std::uint32_t* c = ijk + 3 * r;
            const bool same = verify_ == Verify::all ? std::memcmp(&rebuilt_[r], &s, sizeof s) == 0 : same_position(s, c);
            if (!same || std::bit_cast<std::uint32_t>(s.radius) != std::bit_cast<std::uint32_t>(radius)) {
                exceptions_.push_back(static_cast<std::uint32_t>(first + r));  // its slot stays zero
                std::memset(p, 0, slot);
                continue;
            }
            if (ib == 2) {
                if ((c[0] | c[1] | c[2]) > 0xffff) {
                    index_bytes_ = 4;
                    goto restart;
                }
                for (int a = 0; a < 3; ++a) {  // one store each (a 6-byte memcpy of a stack array stalls)
                    const auto v = static_cast<std::uint16_t>(c[a]);
                    std::memcpy(p + 2 * a, &v, 2);
                }
            } else {
                std::memcpy(p, c, 12);
            }
            if (!put_corners(s.corner, coding_, p + 3 * ib)) {
                coding_ = wider(coding_, s.corner);
                goto restart;
            }
        }
    }
    const std::size_t bytes = base + exceptions_.size() * kExceptionBytes;
    if (bytes > n * sizeof(SampleRecord) / 2) return false;
    out.resize(bytes);
    p = out.data();
    put<std::uint8_t>(p, coding_);
    put<std::uint8_t>(p, static_cast<std::uint8_t>(ib));
    put<std::uint16_t>(p, 0);
    put<std::uint32_t>(p, static_cast<std::uint32_t>(exceptions_.size()));
    put<float>(p, radius);
    put<std::uint32_t>(p, 0);
    for (double v : grid_.origin) put<double>(p, v);
    for (double v : grid_.spacing) put<double>(p, v);
    p = out.data() + base;
    for (std::uint32_t r : exceptions_) {
        put<std::uint32_t>(p, r);
        std::memcpy(p, &rec[r], sizeof(SampleRecord));
        p += sizeof(SampleRecord);
    }
    return true;
}

void SampleCellDecoder::check(const void* payload, std::size_t bytes, std::uint64_t count) {
    (void)header(payload, bytes, count);
}

SampleCellDecoder::Header SampleCellDecoder::header(const void* payload, std::size_t bytes, std::uint64_t count) {
    if (bytes < kSampleCellHeaderBytes)
        throw FormatError("cell-indexed sample frame of " + std::to_string(bytes) + " bytes, shorter than its header");
    const unsigned char* p = static_cast<const unsigned char*>(payload);
    Header h;
    h.coding = get<std::uint8_t>(p);
    h.index_bytes = get<std::uint8_t>(p);
    const auto zero16 = get<std::uint16_t>(p);
    h.exceptions = get<std::uint32_t>(p);
    h.radius = get<float>(p);
    const auto zero32 = get<std::uint32_t>(p);
    for (double& v : h.grid.origin) v = get<double>(p);
    for (double& v : h.grid.spacing) v = get<double>(p);
    if (h.coding < kU8 || h.coding > kF32) throw FormatError("cell-indexed sample frame: unknown corner coding " + std::to_string(h.coding));
    if (h.index_bytes != 2 && h.index_bytes != 4)
        throw FormatError("cell-indexed sample frame: index width " + std::to_string(h.index_bytes) + " (expected 2 or 4)");
    if (zero16 != 0 || zero32 != 0) throw FormatError("cell-indexed sample frame: reserved header bytes are not zero");
    for (int a = 0; a < 3; ++a)
        if (!std::isfinite(h.grid.origin[a]) || !std::isfinite(h.grid.spacing[a]))
            throw FormatError("cell-indexed sample frame: grid origin or spacing is not finite");
    if (h.exceptions > count)
        throw FormatError("cell-indexed sample frame: " + std::to_string(h.exceptions) + " exceptions for " + std::to_string(count) +
                          " records");
    const std::size_t slot = 3 * static_cast<std::size_t>(h.index_bytes) + 8 * corner_bytes(h.coding);
    // count and exceptions are at most 2^32 records here: no product overflows
    if (count > (std::uint64_t{1} << 32))
        throw FormatError("cell-indexed sample frame of " + std::to_string(bytes) + " bytes claims " + std::to_string(count) + " records");
    const std::uint64_t want = kSampleCellHeaderBytes + count * slot + std::uint64_t{h.exceptions} * kExceptionBytes;
    if (want != bytes)
        throw FormatError("cell-indexed sample frame of " + std::to_string(count) + " records has " + std::to_string(bytes) +
                          " bytes (the header implies " + std::to_string(want) + ")");
    return h;
}

void SampleCellDecoder::decode(const void* payload, std::size_t bytes, std::uint64_t count, SampleRecord* out) {
    const Header h = header(payload, bytes, count);
    const unsigned char* p = static_cast<const unsigned char*>(payload) + kSampleCellHeaderBytes;
    const unsigned char* const end = static_cast<const unsigned char*>(payload) + bytes;
    const std::uint8_t coding = h.coding, ib = h.index_bytes;
    const std::uint32_t exceptions = h.exceptions;
    const float radius = h.radius;
    const CellGrid& g = h.grid;
    std::uint32_t ijk[3 * kStep];
    std::uint8_t u8[8 * kStep];
    for (std::uint64_t first = 0; first < count; first += kStep) {
        const std::size_t m = static_cast<std::size_t>(std::min<std::uint64_t>(kStep, count - first));
        SampleRecord* rec = out + first;
        if (coding == kU8) {  // the integer path: no corner floats to convert back
            for (std::size_t r = 0; r < m; ++r) {
                for (int a = 0; a < 3; ++a) ijk[3 * r + a] = ib == 2 ? get<std::uint16_t>(p) : get<std::uint32_t>(p);
                std::memcpy(u8 + 8 * r, p, 8);
                p += 8;
                rec[r].radius = radius;
            }
            complete_centre_samples_u8(g.origin, g.spacing, ijk, u8, rec, m, table_);
            continue;
        }
        for (std::size_t r = 0; r < m; ++r) {
            for (int a = 0; a < 3; ++a) ijk[3 * r + a] = ib == 2 ? get<std::uint16_t>(p) : get<std::uint32_t>(p);
            float* c = rec[r].corner;
            switch (coding) {
                case kI16:
                    for (int q = 0; q < 8; ++q) c[q] = static_cast<float>(get<std::int16_t>(p));
                    break;
                case kU16:
                    for (int q = 0; q < 8; ++q) c[q] = static_cast<float>(get<std::uint16_t>(p));
                    break;
                default:
                    std::memcpy(c, p, 32);
                    p += 32;
            }
            rec[r].radius = radius;
        }
        complete_centre_samples(g.origin, g.spacing, ijk, rec, m);
    }
    std::uint64_t next = 0;
    for (std::uint32_t e = 0; e < exceptions; ++e) {
        const auto r = get<std::uint32_t>(p);
        if (r < next || r >= count)
            throw FormatError("cell-indexed sample frame: exception " + std::to_string(e) + " names record " + std::to_string(r) +
                              (r >= count ? " of " + std::to_string(count) : ", out of order"));
        std::memcpy(&out[r], p, sizeof(SampleRecord));
        p += sizeof(SampleRecord);
        next = std::uint64_t{r} + 1;
    }
    if (p != end) throw FormatError("cell-indexed sample frame: payload size mismatch");  // unreachable after the size check
}

}  // namespace meshless
