// The GDCM boundary (formats/dicom_slice.hpp): the only source file that includes GDCM. Every file
// is walked first (formats/dicom_structure.hpp: Debian's GDCM asserts on malformed elements). Attributes
// are taken from the data set GDCM parsed up to Pixel Data; the pixels through gdcm::ImageReader
// after the file has proven the bytes they claim. RLE Lossless is checked and decoded by
// formats/dicom_rle.hpp; the other compressed transfer syntaxes (the JPEG family) by GDCM in a child
// process (formats/isolated_call.hpp): GDCM's decoders assert (abort) on damaged streams, which then
// fail one file in one line instead of the process.
#include "formats/dicom_slice.hpp"

#include <gdcmDataSet.h>
#include <gdcmFile.h>
#include <gdcmFileMetaInformation.h>
#include <gdcmGlobal.h>
#include <gdcmDicts.h>
#include <gdcmImage.h>
#include <gdcmImageReader.h>
#include <gdcmReader.h>
#include <gdcmTag.h>
#include <gdcmTrace.h>
#include <gdcmTransferSyntax.h>

#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <new>
#include <vector>

#include "formats/binary_file.hpp"
#include "formats/dicom_rle.hpp"
#include "formats/dicom_structure.hpp"
#include "formats/isolated_call.hpp"
#include "formats/text_header.hpp"
#include "kernels/checked_size.hpp"
#include "kernels/errors.hpp"

namespace meshless {

namespace {

const gdcm::Tag kPixelData(0x7fe0, 0x0010);

// GDCM writes warnings and errors to std::cerr; a message of ours says what went wrong, in one line.
void quiet_gdcm() {
    static std::once_flag once;
    std::call_once(once, [] {
        gdcm::Trace::SetDebug(false);
        gdcm::Trace::SetWarning(false);
        gdcm::Trace::SetError(false);
    });
}

// An element's bytes (nullptr/0 when absent or not a plain value).
std::string_view bytes_of(const gdcm::DataSet& ds, const gdcm::Tag& t) {
    if (!ds.FindDataElement(t)) return {};
    const gdcm::DataElement& de = ds.GetDataElement(t);
    const gdcm::ByteValue* bv = de.GetByteValue();
    if (!bv || !bv->GetPointer()) return {};
    return std::string_view(bv->GetPointer(), bv->GetLength());
}

// A text value without its padding (trailing blanks and NULs, leading blanks).
std::string text_of(const gdcm::DataSet& ds, const gdcm::Tag& t) {
    std::string_view v = bytes_of(ds, t);
    while (!v.empty() && (v.back() == ' ' || v.back() == '\0')) v.remove_suffix(1);
    while (!v.empty() && v.front() == ' ') v.remove_prefix(1);
    return std::string(v);
}

std::string tag_name(const gdcm::Tag& t) {
    char buf[16];
    std::snprintf(buf, sizeof buf, "(%04X,%04X)", t.GetGroup(), t.GetElement());
    return buf;
}

// A decimal string (DS/IS) value of exactly n numbers separated by backslashes.
template <std::size_t N>
std::optional<std::array<double, N>> numbers_of(const gdcm::DataSet& ds, const gdcm::Tag& t, const std::string& path,
                                                const char* name) {
    const std::string v = text_of(ds, t);
    if (v.empty()) return std::nullopt;
    std::array<double, N> r{};
    std::size_t at = 0;
    for (std::size_t i = 0; i < N; ++i) {
        const std::size_t end = std::min(v.find('\\', at), v.size());
        const std::string tok = trim(std::string_view(v).substr(at, end - at));
        char* stop = nullptr;
        errno = 0;
        const double x = tok.empty() ? 0.0 : std::strtod(tok.c_str(), &stop);
        if (tok.empty() || stop != tok.c_str() + tok.size() || errno == ERANGE || !std::isfinite(x) ||
            (i + 1 < N && end == v.size()) || (i + 1 == N && end != v.size()))
            throw FormatError(path + ": bad " + name + " " + tag_name(t) + " '" + escape_field(v) + "' (expected " +
                              std::to_string(N) + " number" + (N > 1 ? "s" : "") + ")");
        r[i] = x;
        at = end + 1;
    }
    return r;
}

// An unsigned short (US) value in the data set's byte order.
std::optional<int> us_of(const gdcm::DataSet& ds, const gdcm::Tag& t, bool big_endian, const std::string& path,
                         const char* name) {
    const std::string_view v = bytes_of(ds, t);
    if (v.empty()) return std::nullopt;
    if (v.size() != 2) throw FormatError(path + ": bad " + std::string(name) + " " + tag_name(t) + " (" + std::to_string(v.size()) + " bytes, expected 2)");
    const auto b0 = static_cast<unsigned char>(v[0]), b1 = static_cast<unsigned char>(v[1]);
    return big_endian ? (b0 << 8) | b1 : (b1 << 8) | b0;
}

// One GDCM read: its exceptions and its failure as one FormatError line naming the file.
template <class Read>
void gdcm_read(Read&& read, const std::string& path, const char* what, const std::string& failed) {
    bool ok = false;
    try {
        ok = read();
    } catch (const std::bad_alloc&) {
        throw FormatError(path + ": unreadable DICOM " + what + " (an element's length is larger than memory)");
    } catch (const std::exception&) {
        ok = false;
    }
    if (!ok) throw FormatError(path + ": " + failed);
}

// GDCM's readers take the image attributes (groups 0008, 0018, 0020, 0028) through gdcm::Attribute,
// which asserts that an element's VR is compatible with the dictionary's (found by fuzz_dicom: Bits
// Stored given another VR aborted the process): such an element is refused here first.
void check_dictionary_vrs(const gdcm::DataSet& ds, const std::string& path) {
    const gdcm::Dicts& dicts = gdcm::Global::GetInstance().GetDicts();
    for (const gdcm::DataElement& de : ds.GetDES()) {
        const gdcm::Tag& t = de.GetTag();
        const std::uint16_t g = t.GetGroup();
        if (g != 0x0008 && g != 0x0018 && g != 0x0020 && g != 0x0028) continue;
        const gdcm::VR dict_vr = dicts.GetDictEntry(t).GetVR();
        if (dict_vr == gdcm::VR::INVALID || de.GetVR() == gdcm::VR::INVALID || dict_vr.Compatible(de.GetVR())) continue;
        throw FormatError(path + ": element " + tag_name(t) + " has the VR '" + escape_field(gdcm::VR::GetVRString(de.GetVR())) +
                          "', the dictionary's is '" + gdcm::VR::GetVRString(dict_vr) + "'");
    }
}

}  // namespace

bool dicom_reader_available() { return true; }

DicomSliceHeader read_dicom_slice_header(const std::string& path) {
    quiet_gdcm();
    DicomSliceHeader h;
    h.file = path;
    h.file_size = regular_file_size(path);
    if (!has_dicom_magic(path)) throw FormatError(path + ": not a DICOM file (no 'DICM' after the 128-byte preamble)");
    check_dicom_structure(path);  // GDCM asserts (aborts) on malformed elements: none reach it
    gdcm::Reader reader;
    reader.SetFileName(path.c_str());
    gdcm_read([&] { return reader.ReadUpToTag(kPixelData); }, path, "data set",
              "unreadable DICOM data set (GDCM could not parse it; truncated or corrupt)");
    const gdcm::File& f = reader.GetFile();
    const gdcm::DataSet& ds = f.GetDataSet();
    check_dictionary_vrs(ds, path);
    const gdcm::TransferSyntax& ts = f.GetHeader().GetDataSetTransferSyntax();
    const bool big = ts.GetSwapCode() == gdcm::SwapCode::BigEndian;
    h.transfer_syntax = text_of(f.GetHeader(), gdcm::Tag(0x0002, 0x0010));
    if (h.transfer_syntax.empty() && ts.GetString()) h.transfer_syntax = ts.GetString();
    h.compressed = ts.IsEncapsulated();
    h.sop_class_uid = text_of(ds, gdcm::Tag(0x0008, 0x0016));
    h.series_uid = text_of(ds, gdcm::Tag(0x0020, 0x000e));
    h.series_description = text_of(ds, gdcm::Tag(0x0008, 0x103e));
    // Pixel Data's element header, where GDCM stopped: its length proven against the file's bytes
    h.has_pixel_data = ds.FindDataElement(kPixelData);
    const std::uint64_t at = reader.GetStreamCurrentPosition();
    if (at < h.file_size) {
        unsigned char e[12] = {};
        FileRangeReader in(path);
        const std::uint64_t n = std::min<std::uint64_t>(12, h.file_size - at);
        in.read_into(at, n, reinterpret_cast<std::byte*>(e));
        const bool tag = n >= 8 && (big ? (e[0] == 0x7f && e[1] == 0xe0 && e[2] == 0x00 && e[3] == 0x10)
                                        : (e[0] == 0xe0 && e[1] == 0x7f && e[2] == 0x10 && e[3] == 0x00));
        if (tag) {
            h.has_pixel_data = true;
            const bool explicit_vr = ts.IsExplicit();
            if (explicit_vr && n < 12) throw FormatError(path + ": truncated Pixel Data element header");
            const unsigned char* l = explicit_vr ? e + 8 : e + 4;
            const std::uint32_t vl = big ? (std::uint32_t{l[0]} << 24 | std::uint32_t{l[1]} << 16 | std::uint32_t{l[2]} << 8 | l[3])
                                         : (std::uint32_t{l[3]} << 24 | std::uint32_t{l[2]} << 16 | std::uint32_t{l[1]} << 8 | l[0]);
            const std::uint64_t after = h.file_size - at - (explicit_vr ? 12 : 8);
            if (vl != 0xffffffffu) {
                if (vl > after)
                    throw FormatError(path + ": truncated: Pixel Data claims " + std::to_string(vl) + " bytes, the file holds " +
                                      std::to_string(after) + " after it");
                h.pixel_data_length = vl;
            }
        }
    }
    h.rows = us_of(ds, gdcm::Tag(0x0028, 0x0010), big, path, "Rows").value_or(0);
    h.columns = us_of(ds, gdcm::Tag(0x0028, 0x0011), big, path, "Columns").value_or(0);
    h.bits_allocated = us_of(ds, gdcm::Tag(0x0028, 0x0100), big, path, "Bits Allocated").value_or(0);
    h.bits_stored = us_of(ds, gdcm::Tag(0x0028, 0x0101), big, path, "Bits Stored").value_or(h.bits_allocated);
    h.pixel_representation = us_of(ds, gdcm::Tag(0x0028, 0x0103), big, path, "Pixel Representation").value_or(0);
    h.samples_per_pixel = us_of(ds, gdcm::Tag(0x0028, 0x0002), big, path, "Samples per Pixel").value_or(1);
    if (auto n = numbers_of<1>(ds, gdcm::Tag(0x0028, 0x0008), path, "Number of Frames")) {
        const double x = (*n)[0];
        if (!(x >= 1 && x <= 1e9) || x != static_cast<double>(static_cast<std::int64_t>(x)))
            throw FormatError(path + ": bad Number of Frames (0028,0008) '" + escape_field(text_of(ds, gdcm::Tag(0x0028, 0x0008))) + "'");
        h.frames = static_cast<std::int64_t>(x);
    }
    h.photometric = text_of(ds, gdcm::Tag(0x0028, 0x0004));
    h.position = numbers_of<3>(ds, gdcm::Tag(0x0020, 0x0032), path, "Image Position (Patient)");
    h.orientation = numbers_of<6>(ds, gdcm::Tag(0x0020, 0x0037), path, "Image Orientation (Patient)");
    h.pixel_spacing = numbers_of<2>(ds, gdcm::Tag(0x0028, 0x0030), path, "Pixel Spacing");
    if (auto s = numbers_of<1>(ds, gdcm::Tag(0x0028, 0x1053), path, "Rescale Slope")) h.slope = (*s)[0];
    if (auto i = numbers_of<1>(ds, gdcm::Tag(0x0028, 0x1052), path, "Rescale Intercept")) h.intercept = (*i)[0];
    h.modality = text_of(ds, gdcm::Tag(0x0008, 0x0060));
    h.rescale_type = text_of(ds, gdcm::Tag(0x0028, 0x1054));
    return h;
}

namespace {
/// GDCM's reading and decoding of the slice's pixels into out (want bytes), checked against its header.
void decode_pixels(const DicomSliceHeader& h, std::uint64_t want, std::byte* out);
/// Bits above Bits Stored masked off, signed pixels sign-extended from Bits Stored.
void mask_bits_stored(const DicomSliceHeader& h, std::uint64_t want, std::byte* out);
/// The longest a compressed slice may take to decode in its child process.
constexpr int kDecodeSeconds = 120;
/// RLE Lossless (PS3.5 Annex G), decoded by formats/dicom_rle.hpp.
constexpr const char* kRleLossless = "1.2.840.10008.1.2.5";
}  // namespace

void decode_dicom_slice(const DicomSliceHeader& h, std::byte* out) {
    quiet_gdcm();
    const std::string& path = h.file;
    if (h.samples_per_pixel != 1 || h.stored_bytes() == 0 || h.frames != 1)
        throw FormatError(path + ": unsupported pixel data (" + std::to_string(h.samples_per_pixel) + " sample(s) per pixel, " +
                          std::to_string(h.bits_allocated) + " bits allocated, " + std::to_string(h.frames) +
                          " frame(s); one 8- or 16-bit sample per pixel, one frame, is read)");
    const std::uint64_t want = checked_mul(checked_mul(static_cast<std::uint64_t>(h.rows), static_cast<std::uint64_t>(h.columns),
                                                       path + ": Rows x Columns"),
                                           static_cast<std::uint64_t>(h.stored_bytes()), path + ": pixel bytes");
    // the file proves the bytes before GDCM allocates them
    const std::uint64_t size = regular_file_size(path);
    if (!h.compressed && (size < want || (h.pixel_data_length && *h.pixel_data_length < want)))
        throw FormatError(path + ": truncated: Rows x Columns (" + std::to_string(h.rows) + " x " + std::to_string(h.columns) +
                          ") takes " + std::to_string(want) + " bytes of pixel data, the file has " +
                          std::to_string(h.pixel_data_length.value_or(size)));
    if (h.compressed && h.pixel_data_length)
        throw FormatError(path + ": compressed transfer syntax " + escape_field(h.transfer_syntax) +
                          " with a defined-length Pixel Data element (encapsulated pixel data has an undefined length)");
    if (h.compressed && want / kDicomMaxCompression > size)
        throw FormatError(path + ": compressed pixel data of " + std::to_string(size) + " bytes cannot hold Rows x Columns (" +
                          std::to_string(h.rows) + " x " + std::to_string(h.columns) + ", more than " +
                          std::to_string(kDicomMaxCompression) + ":1)");
    const DicomStructure structure = check_dicom_structure(path);  // as read_dicom_slice_header: the file may have changed since
    {
        gdcm::Reader header;  // the attributes ImageReader takes, checked as read_dicom_slice_header checks them
        header.SetFileName(path.c_str());
        gdcm_read([&] { return header.ReadUpToTag(kPixelData); }, path, "data set",
                  "unreadable DICOM data set (GDCM could not parse it; truncated or corrupt)");
        check_dictionary_vrs(header.GetFile().GetDataSet(), path);
    }
    if (h.compressed && h.transfer_syntax == kRleLossless) {  // checked and decoded here (formats/dicom_rle.hpp)
        const std::uint64_t from = structure.pixel_data_value_at;
        if (from == 0) throw FormatError(path + ": no Pixel Data element to decode");
        FileRangeReader in(path);
        if (from > in.size()) throw FormatError(path + ": truncated RLE pixel data element");
        std::vector<unsigned char> element(static_cast<std::size_t>(in.size() - from));
        in.read_into(from, element.size(), reinterpret_cast<std::byte*>(element.data()));
        decode_rle_pixel_data(element, from, static_cast<std::uint64_t>(h.rows) * static_cast<std::uint64_t>(h.columns),
                              h.stored_bytes() * h.samples_per_pixel, path, out);
    } else if (!h.compressed) {
        decode_pixels(h, want, out);
    } else {  // GDCM's decoders (RLE, JPEG family) assert on damaged streams (fuzz_dicom: RLECodec::Decode)
        const IsolatedResult r = run_isolated(want, out, [&](std::byte* dst) { decode_pixels(h, want, dst); }, kDecodeSeconds);
        const std::string syntax = "transfer syntax " + escape_field(h.transfer_syntax);
        switch (r.outcome) {
            case IsolatedResult::Outcome::ok: break;
            case IsolatedResult::Outcome::error: throw FormatError(r.message.rfind(path, 0) == 0 ? r.message : path + ": " + r.message);
            case IsolatedResult::Outcome::crashed:
                if (r.signal == SIGKILL)  // (the OOM killer, or a user: not the file's fault)
                    throw IoError(path + ": the process decoding its compressed pixel data (" + syntax +
                                  ") was killed (SIGKILL: out of memory, or killed by hand)");
                throw FormatError(path + ": cannot decode the compressed pixel data (" + syntax + "): GDCM's decoder failed on it (" +
                                  (r.signal == SIGABRT ? std::string("assertion, SIGABRT") : "signal " + std::to_string(r.signal)) +
                                  "); the stream is damaged or not of that syntax");
            case IsolatedResult::Outcome::timed_out:
                throw FormatError(path + ": cannot decode the compressed pixel data (" + syntax + "): GDCM's decoder ran over " +
                                  std::to_string(kDecodeSeconds) + " s on one slice (a damaged stream?)");
        }
    }
    mask_bits_stored(h, want, out);
}

namespace {

void decode_pixels(const DicomSliceHeader& h, std::uint64_t want, std::byte* out) {
    const std::string& path = h.file;
    gdcm::ImageReader reader;
    reader.SetFileName(path.c_str());
    gdcm_read([&] { return reader.Read(); }, path, "pixel data",
              "unreadable DICOM image (GDCM could not read its pixel data; truncated, corrupt or not an image)");
    const gdcm::Image& img = reader.GetImage();
    const gdcm::PixelFormat& pf = img.GetPixelFormat();
    if (img.GetNumberOfDimensions() != 2 || img.GetDimension(0) != h.columns || img.GetDimension(1) != h.rows ||
        pf.GetSamplesPerPixel() != 1 || pf.GetBitsAllocated() != h.bits_allocated)
        throw FormatError(path + ": the decoded image (" + std::to_string(img.GetDimension(0)) + " x " +
                          std::to_string(img.GetDimension(1)) + ", " + std::to_string(pf.GetBitsAllocated()) +
                          " bits) is not the header's Columns x Rows (" + std::to_string(h.columns) + " x " +
                          std::to_string(h.rows) + ", " + std::to_string(h.bits_allocated) + " bits)");
    if (!h.compressed) {  // the element itself must hold the pixels (a short element is truncated data)
        const gdcm::DataSet& ds = reader.GetFile().GetDataSet();
        const gdcm::ByteValue* bv = ds.FindDataElement(kPixelData) ? ds.GetDataElement(kPixelData).GetByteValue() : nullptr;
        if (!bv || static_cast<std::uint64_t>(bv->GetLength()) < want)
            throw FormatError(path + ": truncated pixel data (" + std::to_string(bv ? static_cast<std::uint64_t>(bv->GetLength()) : std::uint64_t{0}) + " bytes, Rows x Columns takes " +
                              std::to_string(want) + ")");
    }
    if (img.GetBufferLength() != want)
        throw FormatError(path + ": decoded pixel data is " + std::to_string(img.GetBufferLength()) + " bytes, Rows x Columns takes " +
                          std::to_string(want));
    bool got = false;
    try {
        got = img.GetBuffer(reinterpret_cast<char*>(out));
    } catch (const std::exception&) {
        got = false;
    }
    if (!got)
        throw FormatError(path + ": cannot decode the pixel data (transfer syntax " + escape_field(h.transfer_syntax) +
                          ": GDCM failed to decode it)");
}

void mask_bits_stored(const DicomSliceHeader& h, std::uint64_t want, std::byte* out) {
    // bits above Bits Stored masked off, signed pixels sign-extended from Bits Stored
    const int bs = h.bits_stored;
    if (bs > 0 && bs < h.bits_allocated) {
        const std::uint64_t n = want / static_cast<std::uint64_t>(h.stored_bytes());
        const std::uint32_t mask = (1u << bs) - 1u, sign = 1u << (bs - 1);
        const bool is_signed = h.pixel_representation == 1;
        if (h.stored_bytes() == 1) {
            auto* p = reinterpret_cast<std::uint8_t*>(out);
            for (std::uint64_t i = 0; i < n; ++i) {
                std::uint32_t v = p[i] & mask;
                if (is_signed && (v & sign)) v |= ~mask;
                p[i] = static_cast<std::uint8_t>(v);
            }
        } else {
            for (std::uint64_t i = 0; i < n; ++i) {
                std::uint16_t raw;
                std::memcpy(&raw, out + 2 * i, 2);
                std::uint32_t v = raw & mask;
                if (is_signed && (v & sign)) v |= ~mask;
                raw = static_cast<std::uint16_t>(v);
                std::memcpy(out + 2 * i, &raw, 2);
            }
        }
    }
}

}  // namespace

}  // namespace meshless
