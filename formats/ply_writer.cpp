// The PLY writer (formats/ply.hpp): one AtomicFile, the header up front (padded when its counts are
// patched on commit), records as packed host-order values; binary little endian on a little-endian
// host is written as it comes, other encodings are converted record by record.
#include <algorithm>
#include <bit>
#include <charconv>
#include <cstring>
#include <stdexcept>

#include "formats/atomic_file.hpp"
#include "formats/ply.hpp"
#include "kernels/errors.hpp"

namespace meshless {

namespace {

double load_host(const std::byte* p, StoredType t) {
    switch (t) {
        case StoredType::i8: { std::int8_t v; std::memcpy(&v, p, 1); return v; }
        case StoredType::u8: { std::uint8_t v; std::memcpy(&v, p, 1); return v; }
        case StoredType::i16: { std::int16_t v; std::memcpy(&v, p, 2); return v; }
        case StoredType::u16: { std::uint16_t v; std::memcpy(&v, p, 2); return v; }
        case StoredType::i32: { std::int32_t v; std::memcpy(&v, p, 4); return v; }
        case StoredType::u32: { std::uint32_t v; std::memcpy(&v, p, 4); return v; }
        case StoredType::f32: { float v; std::memcpy(&v, p, 4); return v; }
        default: { double v; std::memcpy(&v, p, 8); return v; }
    }
}

}  // namespace

struct PlyWriter::Impl {
    std::unique_ptr<AtomicFile> file;
    PlyHeader h;
    PlyCounts mode;
    std::vector<std::uint64_t> counts;
    std::vector<std::size_t> count_offsets;  // patched: offset of each element line
    std::size_t elem = 0;
    bool raw = false;  // packed host order is the file's encoding
    std::string text;

    void settle() {
        if (mode == PlyCounts::patched) return;
        while (elem < h.elements.size() && counts[elem] == h.elements[elem].count) ++elem;
    }

    /// Walks (and for non-raw encodings converts) whole records in `data`; returns how many.
    std::uint64_t walk(const PlyElement& e, const std::byte* data, std::size_t bytes, bool encode) {
        const bool be = h.encoding == PlyEncoding::binary_big_endian;
        const bool ascii = h.encoding == PlyEncoding::ascii;
        std::size_t off = 0;
        std::uint64_t n = 0;
        auto need = [&](std::size_t k) {
            if (bytes - off < k) throw std::invalid_argument(file->path() + ": PLY write ends inside a '" + e.name + "' record");
        };
        auto put = [&](const std::byte* v, StoredType t, bool first) {
            const std::size_t s = stored_size(t);
            if (ascii) {
                if (!first) text += ' ';
                char b[64];
                std::to_chars_result r;
                if (t == StoredType::f32) { float x; std::memcpy(&x, v, 4); r = std::to_chars(b, b + sizeof b, x); }
                else if (t == StoredType::f64) { double x; std::memcpy(&x, v, 8); r = std::to_chars(b, b + sizeof b, x); }
                else r = std::to_chars(b, b + sizeof b, static_cast<long long>(load_host(v, t)));
                text.append(b, r.ptr);
            } else {
                unsigned char b[8];
                std::memcpy(b, v, s);
                if (be == (std::endian::native == std::endian::little)) std::reverse(b, b + s);
                text.append(reinterpret_cast<const char*>(b), s);
            }
        };
        while (off < bytes) {
            bool first = true;
            for (const auto& p : e.props) {
                const StoredType t = p.is_list ? p.count_type : p.type;
                need(stored_size(t));
                const double c = p.is_list ? load_host(data + off, t) : 0;
                if (encode) put(data + off, t, first);
                first = false;
                off += stored_size(t);
                if (!p.is_list) continue;
                if (c < 0) throw std::invalid_argument(file->path() + ": negative PLY list length");
                const auto items = static_cast<std::size_t>(c);
                const std::size_t is = stored_size(p.type);
                if (items > (bytes - off) / is) need(bytes);  // throws
                for (std::size_t q = 0; q < items; ++q, off += is)
                    if (encode) put(data + off, p.type, false);
            }
            if (encode && ascii) text += '\n';
            ++n;
            if (encode && text.size() >= (1u << 20)) {
                file->write(text);
                text.clear();
            }
        }
        return n;
    }
};

PlyWriter::PlyWriter(const std::string& path, PlyHeader header, PlyCounts counts) : d_(std::make_unique<Impl>()) {
    Impl& d = *d_;
    d.file = std::make_unique<AtomicFile>(path);
    d.mode = counts;
    if (counts == PlyCounts::patched) {
        if (d.file->is_streaming())
            throw IoError(path + ": a PLY output that cannot seek needs its counts up front (write the whole set at once)");
        for (auto& e : header.elements) e.count = 0;
    }
    d.h = std::move(header);
    d.counts.assign(d.h.elements.size(), 0);
    d.raw = d.h.encoding == PlyEncoding::binary_little_endian && std::endian::native == std::endian::little;
    const std::string text = format_ply_header(d.h, counts != PlyCounts::declared);
    if (counts == PlyCounts::patched)
        for (const auto& e : d.h.elements) d.count_offsets.push_back(text.find("element " + e.name + " 0\ncomment"));
    d.file->write(text);
    d.settle();
}

PlyWriter::~PlyWriter() = default;

void PlyWriter::append(const void* data, std::size_t bytes) {
    Impl& d = *d_;
    if (bytes == 0) return;
    d.settle();
    if (d.elem >= d.h.elements.size())
        throw std::logic_error(d.file->path() + ": PLY write past the last element's declared count");
    const PlyElement& e = d.h.elements[d.elem];
    const auto* p = static_cast<const std::byte*>(data);
    std::uint64_t n;
    if (d.raw && !e.has_lists()) {
        const std::size_t rs = e.min_record_bytes();
        if (bytes % rs) throw std::invalid_argument(d.file->path() + ": PLY write ends inside a '" + e.name + "' record");
        n = bytes / rs;
    } else {
        n = d.walk(e, p, bytes, false);
    }
    if (d.mode != PlyCounts::patched && n > e.count - d.counts[d.elem])
        throw std::logic_error(d.file->path() + ": more '" + e.name + "' records than the PLY header declares");
    if (d.raw) {
        d.file->write(data, bytes);
    } else {
        d.walk(e, p, bytes, true);
        d.file->write(d.text);
        d.text.clear();
    }
    d.counts[d.elem] += n;
    d.settle();
}

void PlyWriter::next_element() {
    if (d_->mode == PlyCounts::patched && d_->elem < d_->h.elements.size()) ++d_->elem;
}

void PlyWriter::commit() {
    Impl& d = *d_;
    for (std::size_t e = 0; e < d.h.elements.size(); ++e) {
        if (d.mode == PlyCounts::patched) {
            const std::string lines = ply_count_lines(d.h.elements[e].name, d.counts[e]);
            d.file->pwrite(d.count_offsets[e], lines.data(), lines.size());
        } else if (d.counts[e] != d.h.elements[e].count) {
            throw std::logic_error(d.file->path() + ": " + std::to_string(d.counts[e]) + " '" + d.h.elements[e].name +
                                   "' records written, the PLY header declares " + std::to_string(d.h.elements[e].count));
        }
    }
    d.file->commit();
}

const std::string& PlyWriter::path() const { return d_->file->path(); }
std::uint64_t PlyWriter::count(std::size_t e) const { return d_->counts.at(e); }

}  // namespace meshless
