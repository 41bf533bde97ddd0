#include "formats/dicom_rle.hpp"

#include <algorithm>
#include <cstring>

#include "kernels/errors.hpp"

namespace meshless {

namespace {

std::uint32_t u32(const unsigned char* p) {
    std::uint32_t v;
    std::memcpy(&v, p, 4);  // (little endian: RLE Lossless is explicit VR little endian)
    return v;
}
std::uint16_t u16(const unsigned char* p) {
    std::uint16_t v;
    std::memcpy(&v, p, 2);
    return v;
}

/// The bytes a PackBits segment gives before its end, stopping once `want` are reached.
std::uint64_t packbits_length(const unsigned char* s, std::uint64_t n, std::uint64_t want, bool& overran) {
    std::uint64_t out = 0, i = 0;
    overran = false;
    while (i < n && out < want) {
        const int c = static_cast<signed char>(s[i++]);
        if (c >= 0) {  // a literal run of c + 1 bytes
            const std::uint64_t len = static_cast<std::uint64_t>(c) + 1;
            if (len > n - i) {
                overran = true;
                return out + (n - i);
            }
            i += len;
            out += len;
        } else if (c != -128) {  // a replicate run: the next byte 1 - c times
            if (i >= n) {
                overran = true;
                return out;
            }
            ++i;
            out += static_cast<std::uint64_t>(1 - c);
        }
    }
    return out;
}


/// The frame's fragment and its segments' [begin, end) offsets in it, checked.
struct RleFrame {
    const unsigned char* fragment = nullptr;
    std::uint32_t segments = 0;
    std::uint32_t off[16] = {};
};

RleFrame locate_rle_frame(std::span<const unsigned char> element, std::uint64_t at, std::uint64_t pixels, int segments,
                          const std::string& path) {
    const auto fail = [&](std::uint64_t off, const std::string& what) {
        return FormatError(path + ": RLE pixel data at byte " + std::to_string(at + off) + ": " + what);
    };
    const std::uint64_t n = element.size();
    const unsigned char* b = element.data();
    // items: (FFFE,E000) u32 length, value; the sequence ends with (FFFE,E0DD) or the element's end
    std::uint64_t pos = 0, items = 0, frag_at = 0, frag_len = 0;
    while (pos + 8 <= n) {
        const std::uint16_t g = u16(b + pos), e = u16(b + pos + 2);
        const std::uint32_t len = u32(b + pos + 4);
        if (g == 0xfffe && e == 0xe0dd) break;
        if (g != 0xfffe || e != 0xe000) throw fail(pos, "expected an item (FFFE,E000)");
        if (len == 0xffffffffu || len > n - pos - 8) throw fail(pos, "an item of " + std::to_string(len) + " bytes past the element's end");
        if (items == 1) {
            frag_at = pos + 8;
            frag_len = len;
        }
        ++items;
        pos += 8 + std::uint64_t{len};
    }
    if (items < 2) throw fail(pos, "no fragment after the Basic Offset Table (one frame expected)");
    if (items > 2) throw fail(pos, std::to_string(items - 1) + " fragments for one frame (RLE puts a frame in one fragment)");
    const unsigned char* f = b + frag_at;
    if (frag_len < 64) throw fail(frag_at, "a fragment of " + std::to_string(frag_len) + " bytes, shorter than the 64-byte RLE header");
    const std::uint32_t count = u32(f);
    if (count != static_cast<std::uint32_t>(segments))
        throw fail(frag_at, std::to_string(count) + " segments, " + std::to_string(segments) + " expected (one per byte of a sample)");
    RleFrame frame;
    frame.fragment = f;
    frame.segments = count;
    std::uint32_t* off = frame.off;
    for (int i = 0; i < 15; ++i) off[i] = u32(f + 4 + 4 * i);
    off[count] = static_cast<std::uint32_t>(frag_len);  // (the last segment ends with the fragment)
    if (off[0] != 64) throw fail(frag_at + 4, "the first segment at " + std::to_string(off[0]) + ", 64 expected");
    for (std::uint32_t i = 1; i < count; ++i)
        if (off[i] <= off[i - 1] || off[i] >= frag_len)
            throw fail(frag_at + 4 + 4 * i, "segment " + std::to_string(i + 1) + " at " + std::to_string(off[i]) +
                                                 " (offsets must increase within the fragment's " + std::to_string(frag_len) + " bytes)");
    for (std::uint32_t i = count; i < 15; ++i)
        if (u32(f + 4 + 4 * i) != 0) throw fail(frag_at + 4 + 4 * i, "offset " + std::to_string(i + 1) + " of an unused segment is not 0");
    for (std::uint32_t i = 0; i < count; ++i) {
        bool overran = false;
        const std::uint64_t got = packbits_length(f + off[i], off[i + 1] - off[i], pixels, overran);
        if (overran) throw fail(frag_at + off[i], "segment " + std::to_string(i + 1) + " has a run past its end");
        if (got < pixels)
            throw fail(frag_at + off[i], "segment " + std::to_string(i + 1) + " decodes to " + std::to_string(got) + " bytes, " +
                                             std::to_string(pixels) + " expected");
    }
    return frame;
}

/// Segment bytes s[0, n) as PackBits runs into every `stride`-th byte of out, `pixels` of them
/// (checked by locate_rle_frame: the runs stay inside the segment and give at least that many).
void unpack(const unsigned char* s, std::uint64_t n, std::uint64_t pixels, std::byte* out, std::size_t stride) {
    std::uint64_t o = 0, i = 0;
    while (i < n && o < pixels) {
        const int c = static_cast<signed char>(s[i++]);
        if (c >= 0) {
            const std::uint64_t len = std::min<std::uint64_t>(static_cast<std::uint64_t>(c) + 1, pixels - o);
            for (std::uint64_t k = 0; k < len; ++k) out[(o + k) * stride] = static_cast<std::byte>(s[i + k]);
            i += static_cast<std::uint64_t>(c) + 1;
            o += len;
        } else if (c != -128) {
            const std::uint64_t len = std::min<std::uint64_t>(static_cast<std::uint64_t>(1 - c), pixels - o);
            const auto v = static_cast<std::byte>(s[i++]);
            for (std::uint64_t k = 0; k < len; ++k) out[(o + k) * stride] = v;
            o += len;
        }
    }
}

}  // namespace

void check_rle_pixel_data(std::span<const unsigned char> element, std::uint64_t at, std::uint64_t pixels, int segments,
                          const std::string& path) {
    (void)locate_rle_frame(element, at, pixels, segments, path);
}

void decode_rle_pixel_data(std::span<const unsigned char> element, std::uint64_t at, std::uint64_t pixels, int segments,
                           const std::string& path, std::byte* out) {
    const RleFrame f = locate_rle_frame(element, at, pixels, segments, path);
    const auto stride = static_cast<std::size_t>(f.segments);
    for (std::uint32_t k = 0; k < f.segments; ++k)  // segment k: byte (segments - 1 - k) of each little-endian sample
        unpack(f.fragment + f.off[k], f.off[k + 1] - f.off[k], pixels, out + (f.segments - 1 - k), stride);
}

}  // namespace meshless
