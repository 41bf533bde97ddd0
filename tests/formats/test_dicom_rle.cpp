// The RLE Lossless structure check (formats/dicom_rle.hpp): a well-formed element passes, and
// one must-fail element per defect class: items, fragments, the RLE header, the segments' runs.
#include <catch2/catch.hpp>

#include <cstdint>
#include <string>
#include <vector>

#include "error_of.hpp"
#include "formats/dicom_rle.hpp"
#include "kernels/errors.hpp"

using namespace meshless;
using meshless::test::error_of;

namespace {

void put32(std::vector<unsigned char>& b, std::size_t at, std::uint32_t v) {
    for (int i = 0; i < 4; ++i) b[at + static_cast<std::size_t>(i)] = static_cast<unsigned char>(v >> (8 * i));
}
void item(std::vector<unsigned char>& b, std::uint16_t element, const std::vector<unsigned char>& value) {
    const std::size_t at = b.size();
    b.resize(at + 8);
    b[at] = 0xfe;
    b[at + 1] = 0xff;
    b[at + 2] = static_cast<unsigned char>(element & 0xff);
    b[at + 3] = static_cast<unsigned char>(element >> 8);
    put32(b, at + 4, static_cast<std::uint32_t>(value.size()));
    b.insert(b.end(), value.begin(), value.end());
}

/// A fragment of `segments` segments, each a literal run of `pixels` (<= 128) bytes then a pad byte.
std::vector<unsigned char> fragment(int segments, int pixels) {
    std::vector<unsigned char> f(64, 0);
    put32(f, 0, static_cast<std::uint32_t>(segments));
    for (int s = 0; s < segments; ++s) {
        put32(f, 4 + 4 * static_cast<std::size_t>(s), static_cast<std::uint32_t>(f.size()));
        f.push_back(static_cast<unsigned char>(pixels - 1));
        for (int i = 0; i < pixels; ++i) f.push_back(static_cast<unsigned char>(s * 10 + i));
        f.push_back(0);
    }
    return f;
}

/// The element: an empty Basic Offset Table, the fragments, the sequence delimiter.
std::vector<unsigned char> element(const std::vector<std::vector<unsigned char>>& fragments) {
    std::vector<unsigned char> b;
    item(b, 0xe000, {});
    for (const auto& f : fragments) item(b, 0xe000, f);
    item(b, 0xe0dd, {});
    return b;
}

const std::string kPasses = "(nothing thrown)";  // (error_of when nothing was thrown)

std::string check(const std::vector<unsigned char>& b, int pixels, int segments) {
    return error_of([&] { check_rle_pixel_data(b, 1000, static_cast<std::uint64_t>(pixels), segments, "s.dcm"); });
}

}  // namespace

TEST_CASE("RLE check: a well-formed element passes, one must-fail element per defect class", "[formats][dicom][rle]") {
    CHECK(check(element({fragment(1, 12)}), 12, 1) == kPasses);
    CHECK(check(element({fragment(2, 12)}), 12, 2) == kPasses);
    CHECK(check(element({fragment(2, 12)}), 10, 2) == kPasses);  // runs beyond the pixels: padding
    const auto fails = [](const std::string& e, const std::string& what) {
        INFO(e);
        CHECK(e.rfind("s.dcm: RLE pixel data at byte ", 0) == 0);
        CHECK(e.find(what) != std::string::npos);
        CHECK(e.find('\n') == std::string::npos);
    };
    // items
    std::vector<unsigned char> b = element({fragment(1, 12)});
    b[0] = 0x00;
    fails(check(b, 12, 1), "expected an item (FFFE,E000)");
    b = element({fragment(1, 12)});
    put32(b, 12, 100000);  // the fragment's length past the element
    fails(check(b, 12, 1), "past the element's end");
    fails(check(element({}), 12, 1), "no fragment after the Basic Offset Table");
    fails(check(element({fragment(1, 12), fragment(1, 12)}), 12, 1), "2 fragments for one frame");
    // the RLE header
    std::vector<unsigned char> f = fragment(1, 12);
    f.resize(40);
    fails(check(element({f}), 12, 1), "shorter than the 64-byte RLE header");
    fails(check(element({fragment(1, 12)}), 12, 2), "1 segments, 2 expected");
    f = fragment(1, 12);
    put32(f, 4, 60);
    fails(check(element({f}), 12, 1), "the first segment at 60, 64 expected");
    f = fragment(2, 12);
    put32(f, 8, 64);  // segment 2 where segment 1 is
    fails(check(element({f}), 12, 2), "segment 2 at 64 (offsets must increase");
    f = fragment(2, 12);
    put32(f, 8, 5000);
    fails(check(element({f}), 12, 2), "segment 2 at 5000");
    f = fragment(1, 12);
    put32(f, 20, 7);
    fails(check(element({f}), 12, 1), "offset 5 of an unused segment is not 0");
    // the runs
    f = fragment(1, 12);
    f[64 + 13] = 0x80;  // the pad byte as PackBits' no-op: the segment ends after 12 bytes
    fails(check(element({f}), 20, 1), "segment 1 decodes to 12 bytes, 20 expected");
    f = fragment(1, 12);
    f[64] = 100;  // a literal run of 101 bytes in a segment of 14
    fails(check(element({f}), 12, 1), "segment 1 has a run past its end");
    f = fragment(1, 12);
    f[64] = 0xfb;  // a replicate run (6 x the next byte), then literal bytes read as runs
    CHECK(check(element({f}), 6, 1) == kPasses);
}

TEST_CASE("RLE decoding: segment k is byte k of each sample, most significant first, out little endian", "[formats][dicom][rle]") {
    // fragment(2, 12): segment 1 holds 0..11 (the high bytes), segment 2 holds 10..21 (the low bytes)
    std::vector<std::byte> out(24);
    decode_rle_pixel_data(element({fragment(2, 12)}), 0, 12, 2, "s.dcm", out.data());
    for (int i = 0; i < 12; ++i) {
        CHECK(static_cast<int>(out[2 * static_cast<std::size_t>(i)]) == 10 + i);
        CHECK(static_cast<int>(out[2 * static_cast<std::size_t>(i) + 1]) == i);
    }
    // a replicate run: 6 copies of the byte after it, then a literal
    std::vector<unsigned char> f(64, 0);
    put32(f, 0, 1);
    put32(f, 4, 64);
    for (unsigned char c : {0xfb, 0x07, 0x01, 0x09, 0x08}) f.push_back(c);
    f.push_back(0);
    std::vector<std::byte> one(9);
    decode_rle_pixel_data(element({f}), 0, 8, 1, "s.dcm", one.data());
    const int want[8] = {7, 7, 7, 7, 7, 7, 9, 8};
    for (int i = 0; i < 8; ++i) CHECK(static_cast<int>(one[static_cast<std::size_t>(i)]) == want[i]);
    CHECK_THROWS_AS(decode_rle_pixel_data(element({f}), 0, 9, 1, "s.dcm", one.data()), FormatError);
}
