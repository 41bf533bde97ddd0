#include "formats/gzip.hpp"

#include <libdeflate.h>
#include <zlib.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <new>

#include "formats/binary_file.hpp"
#include "formats/mapped_file.hpp"
#include "kernels/checked_size.hpp"
#include "kernels/errors.hpp"

namespace meshless {

struct InflateReader::Impl {
    std::string path;
    std::FILE* f = nullptr;
    z_stream zs{};
    bool z_open = false;
    bool eof_in = false;
    bool finished = false;
    bool member_ended = false;  // inflate reported the end of a zlib stream or gzip member
    std::vector<unsigned char> in;
    std::uint64_t pos = 0;

    ~Impl() {
        if (z_open) inflateEnd(&zs);
        if (f) std::fclose(f);
    }
    void refill() {
        if (eof_in) return;
        const std::size_t got = std::fread(in.data(), 1, in.size(), f);
        if (got < in.size()) {
            if (std::ferror(f)) throw IoError(path + ": read failed: " + std::strerror(errno));
            eof_in = true;
        }
        zs.next_in = in.data();
        zs.avail_in = static_cast<uInt>(got);
    }
    // True when the unread input starts with the gzip magic (reading more input when fewer than
    // two bytes are buffered).
    bool at_gzip_magic() {
        if (zs.avail_in < 2 && !eof_in) {
            const std::size_t keep = zs.avail_in;
            if (keep) std::memmove(in.data(), zs.next_in, keep);
            const std::size_t got = std::fread(in.data() + keep, 1, in.size() - keep, f);
            if (got < in.size() - keep) {
                if (std::ferror(f)) throw IoError(path + ": read failed: " + std::strerror(errno));
                eof_in = true;
            }
            zs.next_in = in.data();
            zs.avail_in = static_cast<uInt>(keep + got);
        }
        return is_gzip_magic(zs.next_in, zs.avail_in);
    }
};

InflateReader::InflateReader(const std::string& path, std::uint64_t offset) : impl_(std::make_unique<Impl>()) {
    impl_->path = path;
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec)) throw IoError(path + ": is a directory, expected a file");
    require_regular_file(path);
    impl_->f = std::fopen(path.c_str(), "rb");
    if (!impl_->f) throw IoError(path + ": cannot open: " + std::strerror(errno));
    if (offset && fseeko(impl_->f, static_cast<off_t>(offset), SEEK_SET) != 0)
        throw IoError(path + ": cannot seek to " + std::to_string(offset));
    impl_->in.resize(1 << 20);
    if (inflateInit2(&impl_->zs, 15 + 32) != Z_OK) throw IoError(path + ": zlib init failed");
    impl_->z_open = true;
}

InflateReader::~InflateReader() = default;

std::uint64_t InflateReader::position() const { return impl_->pos; }

std::size_t InflateReader::read(void* dst, std::size_t n) {
    Impl& m = *impl_;
    auto* out = static_cast<unsigned char*>(dst);
    std::size_t done = 0;
    while (done < n && !m.finished) {
        if (m.member_ended) {  // another gzip member may follow; anything else after the last one is padding
            if (!m.at_gzip_magic()) {
                m.finished = true;
                break;
            }
            inflateReset(&m.zs);
            m.member_ended = false;
        }
        if (m.zs.avail_in == 0) {
            m.refill();
            if (m.zs.avail_in == 0)
                throw FormatError(m.path + ": compressed data ends unexpectedly after " +
                                  std::to_string(m.pos + done) + " decompressed bytes");
        }
        const std::size_t chunk = std::min<std::size_t>(n - done, 1u << 30);
        m.zs.next_out = out + done;
        m.zs.avail_out = static_cast<uInt>(chunk);
        const int r = inflate(&m.zs, Z_NO_FLUSH);
        done += chunk - m.zs.avail_out;
        if (r == Z_STREAM_END) {
            m.member_ended = true;
        } else if (r != Z_OK && r != Z_BUF_ERROR) {
            throw FormatError(m.path + ": corrupt compressed data: " + (m.zs.msg ? m.zs.msg : "inflate error"));
        }
    }
    m.pos += done;
    return done;
}

void InflateReader::read_exact(void* dst, std::size_t n, const char* what) {
    const std::uint64_t before = impl_->pos;
    const std::size_t got = read(dst, n);
    if (got != n)
        throw FormatError(impl_->path + ": compressed " + what + " ends after " + std::to_string(before + got) +
                          " bytes, expected " + std::to_string(before + n));
}

void InflateReader::expect_end(std::uint64_t expected) {
    Impl& m = *impl_;
    // the member that delivered the last byte must end without another byte, and no further
    // gzip member may follow it (gzip_tail_rule in gzip.hpp)
    while (!m.finished && !m.member_ended) {
        if (m.zs.avail_in == 0) {
            m.refill();
            if (m.zs.avail_in == 0)
                throw FormatError(m.path + ": compressed data ends unexpectedly after " + std::to_string(m.pos) +
                                  " decompressed bytes");
        }
        unsigned char extra = 0;
        m.zs.next_out = &extra;
        m.zs.avail_out = 1;
        const uInt before = m.zs.avail_in;
        const int r = inflate(&m.zs, Z_NO_FLUSH);
        if (m.zs.avail_out == 0) throw FormatError(gzip_overrun_message(m.path, expected));
        if (r == Z_STREAM_END) m.member_ended = true;
        else if ((r != Z_OK && r != Z_BUF_ERROR) || (r == Z_BUF_ERROR && m.zs.avail_in == before && before))
            throw FormatError(m.path + ": corrupt compressed data: " + (m.zs.msg ? m.zs.msg : "inflate error"));
    }
    if (m.member_ended && m.at_gzip_magic()) throw FormatError(gzip_overrun_message(m.path, expected));
    m.finished = true;
}

void InflateReader::skip(std::uint64_t n) {
    std::vector<unsigned char> buf(std::min<std::uint64_t>(n, 1 << 16));
    while (n) {
        const std::size_t k = static_cast<std::size_t>(std::min<std::uint64_t>(n, buf.size()));
        read_exact(buf.data(), k, "payload");
        n -= k;
    }
}

namespace {

struct DecompressorFree {
    void operator()(libdeflate_decompressor* d) const { libdeflate_free_decompressor(d); }
};

}  // namespace

void inflate_into(const std::byte* data, std::size_t n, std::byte* dst, std::size_t expected, const std::string& path) {
    const std::unique_ptr<libdeflate_decompressor, DecompressorFree> d(libdeflate_alloc_decompressor());
    if (!d) throw std::bad_alloc();
    const bool gzip = is_gzip_magic(data, n);
    std::size_t in = 0, out = 0;
    for (;;) {
        if (in == n)
            throw FormatError(path + ": compressed data ends after " + std::to_string(out) + " decompressed bytes, expected " +
                              std::to_string(expected));
        std::size_t used = 0, made = 0;
        const libdeflate_result r =
            gzip ? libdeflate_gzip_decompress_ex(d.get(), data + in, n - in, dst + out, expected - out, &used, &made)
                 : libdeflate_zlib_decompress_ex(d.get(), data + in, n - in, dst + out, expected - out, &used, &made);
        if (r == LIBDEFLATE_INSUFFICIENT_SPACE)
            throw FormatError(gzip_overrun_message(path, expected));
        if (r != LIBDEFLATE_SUCCESS)
            throw FormatError(path + ": corrupt compressed data (a damaged or truncated " + (gzip ? "gzip member" : "zlib stream") +
                              (out ? " after " + std::to_string(out) + " decompressed bytes)" : ")"));
        in += used;
        out += made;
        if (out == expected) {  // gzip_tail_rule: a further member is refused, other bytes are padding
            if (is_gzip_magic(data + in, n - in)) throw FormatError(gzip_overrun_message(path, expected));
            return;
        }
        if (!gzip || !is_gzip_magic(data + in, n - in))  // no further gzip member
            throw FormatError(path + ": compressed data ends after " + std::to_string(out) + " decompressed bytes, expected " +
                              std::to_string(expected));
    }
}

SampleBytes inflate_file(const std::string& path, std::uint64_t offset, std::uint64_t skip, std::uint64_t n) {
    const std::uint64_t size = regular_file_size(path);
    const std::uint64_t avail = size - std::min(size, offset);
    const std::uint64_t total = checked_add(skip, n, path + ": decompressed size");
    if (total / kMaxDeflateRatio > avail + 64)
        throw FormatError(path + ": " + std::to_string(total) + " decompressed bytes claimed, more than the " +
                          std::to_string(avail) + " compressed bytes after offset " + std::to_string(offset) + " can hold");
    if (total > std::numeric_limits<std::size_t>::max()) throw FormatError(path + ": decompressed size too large");
    const SampleBytes in = map_file_range(path, std::min(size, offset), avail);
    // zero pages that become resident only as libdeflate writes the inflated data into them
    void* p = total ? std::calloc(static_cast<std::size_t>(total), 1) : nullptr;
    if (total && !p) throw std::bad_alloc();
    const std::shared_ptr<void> owner(p, std::free);
    auto* out = static_cast<std::byte*>(p);
    inflate_into(in.data(), in.size(), out, static_cast<std::size_t>(total), path);
    if (n == 0) return SampleBytes();
    return SampleBytes::adopt(out + skip, static_cast<std::size_t>(n), owner);
}

std::string gzip_overrun_message(const std::string& path, std::uint64_t expected) {
    return path + ": compressed data decompresses to more than " + std::to_string(expected) + " bytes";
}

bool is_gzip_magic(const void* data, std::size_t n) {
    const auto* p = static_cast<const unsigned char*>(data);
    return n >= 2 && p[0] == 0x1f && p[1] == 0x8b;
}

}  // namespace meshless
