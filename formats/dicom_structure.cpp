// The element walk of formats/dicom_structure.hpp.
#include "formats/dicom_structure.hpp"

#include <cstdint>
#include <cstdio>
#include <string_view>

#include "formats/binary_file.hpp"
#include "kernels/errors.hpp"

namespace meshless {

namespace {

constexpr std::uint32_t kUndefined = 0xffffffffu;
constexpr int kMaxDepth = 32;

struct Header {
    std::uint16_t group = 0, element = 0;
    char vr[3] = {0, 0, 0};  // empty: implicit, or an item tag
    std::uint32_t length = 0;
    std::uint64_t value_at = 0;
};

class Walker {
public:
    explicit Walker(const std::string& path) : path_(path), in_(path), size_(regular_file_size(path)) {}

    void run() {
        if (size_ < 132) fail(0, "shorter than the 128-byte preamble and 'DICM'");
        std::uint64_t at = 132;
        std::string syntax;
        // File Meta Information: explicit VR little endian, group 0002
        while (at < size_) {
            unsigned char b[2];
            read(at, 2, b);
            if ((b[0] | b[1] << 8) != 0x0002) break;
            const Header h = header(at, true, false);
            if (h.length == kUndefined) fail(at, "undefined length in the File Meta Information");
            fits(at, h, size_);
            if (h.element == 0x0010) {
                std::string v(std::min<std::uint32_t>(h.length, 64), '\0');
                read(h.value_at, v.size(), reinterpret_cast<unsigned char*>(v.data()));
                while (!v.empty() && (v.back() == '\0' || v.back() == ' ')) v.pop_back();
                syntax = v;
            }
            at = h.value_at + h.length;
        }
        if (syntax.empty()) fail(at, "no Transfer Syntax UID (0002,0010) in the File Meta Information");
        if (at >= size_) fail(at, "no data set after the File Meta Information");
        if (syntax == "1.2.840.10008.1.2.1.99")
            throw FormatError(path_ + ": unsupported DICOM transfer syntax 1.2.840.10008.1.2.1.99 (deflated data set)");
        const bool explicit_vr = syntax != "1.2.840.10008.1.2";
        const bool big = syntax == "1.2.840.10008.1.2.2";
        encapsulated_ = explicit_vr && syntax != "1.2.840.10008.1.2.1" && !big;
        walk(at, size_, explicit_vr, big, 0, false);
    }

    DicomStructure found() const { return found_; }

private:
    DicomStructure found_;
    bool encapsulated_ = false;  ///< the transfer syntax is none of the three uncompressed ones
    [[noreturn]] void fail(std::uint64_t at, const std::string& what) const {
        throw FormatError(path_ + ": malformed DICOM at byte " + std::to_string(at) + ": " + what);
    }

    void read(std::uint64_t at, std::uint64_t n, unsigned char* out) {
        if (at > size_ || n > size_ - at) fail(at, "truncated (an element header runs past the end of the file)");
        in_.read_into(at, n, reinterpret_cast<std::byte*>(out));
    }

    static std::uint16_t u16(const unsigned char* p, bool big) { return big ? static_cast<std::uint16_t>(p[0] << 8 | p[1]) : static_cast<std::uint16_t>(p[1] << 8 | p[0]); }
    static std::uint32_t u32(const unsigned char* p, bool big) {
        return big ? (std::uint32_t{p[0]} << 24 | std::uint32_t{p[1]} << 16 | std::uint32_t{p[2]} << 8 | p[3])
                   : (std::uint32_t{p[3]} << 24 | std::uint32_t{p[2]} << 16 | std::uint32_t{p[1]} << 8 | p[0]);
    }

    static std::string tag_text(const Header& h) {
        char buf[16];
        std::snprintf(buf, sizeof buf, "(%04X,%04X)", h.group, h.element);
        return buf;
    }

    Header header(std::uint64_t at, bool explicit_vr, bool big) {
        unsigned char b[12];
        read(at, 8, b);
        Header h;
        h.group = u16(b, big);
        h.element = u16(b + 2, big);
        if (h.group == 0xfffe || !explicit_vr) {  // items and their delimiters carry no VR
            h.length = u32(b + 4, big);
            h.value_at = at + 8;
            return h;
        }
        h.vr[0] = static_cast<char>(b[4]);
        h.vr[1] = static_cast<char>(b[5]);
        if (h.vr[0] < 'A' || h.vr[0] > 'Z' || h.vr[1] < 'A' || h.vr[1] > 'Z') fail(at, "element " + tag_text(h) + " has no valid VR");
        const std::string_view vr(h.vr, 2);
        // the VRs GDCM 3.0 reads: the 64-bit ones (OV, SV, UV) and unknown codes reach an assertion in
        // its explicit-VR reader (found by fuzz_dicom), so they are refused here
        static constexpr std::string_view kKnown[] = {"AE", "AS", "AT", "CS", "DA", "DS", "DT", "FL", "FD", "IS", "LO",
                                                      "LT", "OB", "OD", "OF", "OL", "OW", "PN", "SH", "SL", "SQ", "SS",
                                                      "ST", "TM", "UC", "UI", "UL", "UN", "UR", "US", "UT"};
        bool known = false;
        for (auto k : kKnown) known = known || vr == k;
        if (!known) fail(at, "element " + tag_text(h) + " has the VR '" + std::string(vr) + "', which this reader does not support");
        static constexpr std::string_view kLong[] = {"OB", "OD", "OF", "OL", "OW", "SQ", "UC", "UN", "UR", "UT"};
        bool long_form = false;
        for (auto l : kLong) long_form = long_form || vr == l;
        if (long_form) {
            read(at, 12, b);
            h.length = u32(b + 8, big);
            h.value_at = at + 12;
        } else {
            h.length = u16(b + 6, big);
            h.value_at = at + 8;
        }
        return h;
    }

    void fits(std::uint64_t at, const Header& h, std::uint64_t end) const {
        if (h.value_at > end || h.length > end - h.value_at)
            fail(at, "truncated: element " + tag_text(h) + " claims " + std::to_string(h.length) + " bytes, " +
                         std::to_string(end > h.value_at ? end - h.value_at : 0) + " are left");
    }

    // Past an item or sequence delimiter, whose length must be 0 (PS3.5 7.5): GDCM allocates a value
    // of the length it claims (fuzz_dicom: 2 GiB from a 12-byte delimiter).
    std::uint64_t delimiter_end(std::uint64_t at, const Header& h) {
        if (h.length != 0) fail(at, "delimiter " + tag_text(h) + " with a length of " + std::to_string(h.length) + " (0 expected)");
        return h.value_at;
    }

    // Elements in [at, end); in an undefined-length item, up to and past its delimiter (returned).
    std::uint64_t walk(std::uint64_t at, std::uint64_t end, bool explicit_vr, bool big, int depth, bool in_undefined_item) {
        while (at < end) {
            const Header h = header(at, explicit_vr, big);
            if (h.group == 0xfffe) {
                if (in_undefined_item && h.element == 0xe00d) return delimiter_end(at, h);
                fail(at, "item tag " + tag_text(h) + " outside a sequence");
            }
            const std::string_view vr(h.vr, h.vr[0] ? 2 : 0);
            const bool pixel = h.group == 0x7fe0 && h.element == 0x0010;
            if (pixel && depth == 0) found_.pixel_data_value_at = h.value_at;
            // (GDCM asserts on Pixel Data inside an item, or of undefined length in an uncompressed syntax)
            if (pixel && depth > 0) fail(at, "Pixel Data (7FE0,0010) inside a sequence item");
            if (pixel && h.length == kUndefined && !encapsulated_)
                fail(at, "Pixel Data (7FE0,0010) of undefined length in an uncompressed transfer syntax");
            if (h.length == kUndefined) {
                if (explicit_vr && vr != "SQ" && vr != "UN" && !pixel)
                    fail(at, "element " + tag_text(h) + " (" + std::string(vr) + ") has an undefined length");
                // UN of undefined length holds implicit VR little endian (PS3.5 6.2.2)
                const bool inner_explicit = explicit_vr && vr != "UN";
                at = sequence(h.value_at, end, inner_explicit, big, depth + 1, pixel);
            } else {
                fits(at, h, end);
                if (vr == "SQ") items(h.value_at, h.value_at + h.length, explicit_vr, big, depth + 1);
                at = h.value_at + h.length;
            }
        }
        if (in_undefined_item) fail(at, "an item without its delimiter");
        return at;
    }

    // An undefined-length sequence (or encapsulated pixel data): items up to (FFFE,E0DD).
    std::uint64_t sequence(std::uint64_t at, std::uint64_t end, bool explicit_vr, bool big, int depth, bool pixel) {
        if (depth > kMaxDepth) fail(at, "sequences nested more than " + std::to_string(kMaxDepth) + " deep");
        for (;;) {
            const Header h = header(at, false, big);
            if (h.group != 0xfffe) fail(at, "expected an item in a sequence, found " + tag_text(h));
            if (h.element == 0xe0dd) return delimiter_end(at, h);
            if (h.element != 0xe000) fail(at, "unexpected " + tag_text(h) + " in a sequence");
            if (h.length == kUndefined) {
                if (pixel) fail(at, "a pixel data fragment of undefined length");
                at = walk(h.value_at, end, explicit_vr, big, depth, true);
            } else {
                fits(at, h, end);
                if (!pixel) walk(h.value_at, h.value_at + h.length, explicit_vr, big, depth, false);
                at = h.value_at + h.length;
            }
        }
    }

    // The items of a defined-length sequence filling [at, end).
    void items(std::uint64_t at, std::uint64_t end, bool explicit_vr, bool big, int depth) {
        if (depth > kMaxDepth) fail(at, "sequences nested more than " + std::to_string(kMaxDepth) + " deep");
        while (at < end) {
            const Header h = header(at, false, big);
            if (h.group != 0xfffe || h.element != 0xe000) fail(at, "expected an item in a sequence, found " + tag_text(h));
            if (h.length == kUndefined) {
                at = walk(h.value_at, end, explicit_vr, big, depth, true);
            } else {
                fits(at, h, end);
                walk(h.value_at, h.value_at + h.length, explicit_vr, big, depth, false);
                at = h.value_at + h.length;
            }
        }
    }

    const std::string& path_;
    FileRangeReader in_;
    std::uint64_t size_;
};

}  // namespace

DicomStructure check_dicom_structure(const std::string& path) {
    Walker w(path);
    w.run();
    return w.found();
}

}  // namespace meshless
