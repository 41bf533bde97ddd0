// The PLY body reader (formats/ply.hpp): a window over a file (1 MiB buffer, bulk reads straight
// into the caller's memory) or over bytes in memory, decoding records element by element.
#include <algorithm>
#include <bit>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include "formats/ply.hpp"
#include "kernels/errors.hpp"

namespace meshless {

namespace {

constexpr std::size_t kBuffer = kPlyMaxHeaderBytes;
constexpr std::size_t kMaxLine = std::size_t(64) << 20;
constexpr std::size_t kChunk = std::size_t(256) << 10;  // smallest read(2) into the buffer

double decode(const std::byte* p, StoredType t, bool swap) {
    unsigned char b[8];
    const std::size_t n = stored_size(t);
    std::memcpy(b, p, n);
    if (swap) std::reverse(b, b + n);
    switch (t) {
        case StoredType::i8: return static_cast<signed char>(b[0]);
        case StoredType::u8: return b[0];
        case StoredType::i16: { std::int16_t v; std::memcpy(&v, b, 2); return v; }
        case StoredType::u16: { std::uint16_t v; std::memcpy(&v, b, 2); return v; }
        case StoredType::i32: { std::int32_t v; std::memcpy(&v, b, 4); return v; }
        case StoredType::u32: { std::uint32_t v; std::memcpy(&v, b, 4); return v; }
        case StoredType::f32: { float v; std::memcpy(&v, b, 4); return v; }
        default: { double v; std::memcpy(&v, b, 8); return v; }
    }
}

/// [lo, hi] of an integer type.
void int_range(StoredType t, double& lo, double& hi) {
    switch (t) {
        case StoredType::i8: lo = -128, hi = 127; break;
        case StoredType::u8: lo = 0, hi = 255; break;
        case StoredType::i16: lo = -32768, hi = 32767; break;
        case StoredType::u16: lo = 0, hi = 65535; break;
        case StoredType::i32: lo = -2147483648.0, hi = 2147483647.0; break;
        default: lo = 0, hi = 4294967295.0; break;
    }
}

bool mul_add(std::uint64_t& acc, std::uint64_t a, std::uint64_t b) {
    std::uint64_t m;
    if (__builtin_mul_overflow(a, b, &m)) return false;
    return !__builtin_add_overflow(acc, m, &acc);
}

}  // namespace

struct PlyReader::Impl {
    std::string name;
    int fd = -1;                         // file mode
    std::unique_ptr<std::byte[]> buf;    // file mode (not zero-filled)
    std::size_t buf_size = 0;
    const std::byte* p = nullptr;        // window [p, p + avail)
    std::size_t avail = 0;
    std::uint64_t offset = 0;            // file offset of p
    bool eof = false;                    // no more bytes beyond the window
    bool size_known = false;
    std::uint64_t total = 0;             // file size when known
    PlyHeader h;
    std::size_t elem = 0;
    std::uint64_t rec = 0;
    std::uint64_t line = 0;              // ASCII: line of the last record read
    bool swap = false, ascii = false;
    std::vector<std::string_view> tok;   // ASCII tokens of the current line
    std::size_t tok_i = 0;

    ~Impl() {
        if (fd >= 0) ::close(fd);
    }

    std::string at() const {
        return ascii ? name + ": line " + std::to_string(line) + ": " : name + ": byte " + std::to_string(offset) + ": ";
    }

    /// Makes at least `need` bytes visible in the window if the input has them; returns whether it does.
    bool fill(std::size_t need) {
        if (avail >= need || eof) return avail >= need;
        if (fd < 0) {
            eof = true;
            return false;
        }
        if (need > buf_size) {
            const std::size_t size = std::max(need, buf_size * 2);
            std::unique_ptr<std::byte[]> bigger(new std::byte[size]);
            if (avail) std::memcpy(bigger.get(), p, avail);
            buf = std::move(bigger);
            buf_size = size;
        } else if (avail && p != buf.get()) {
            std::memmove(buf.get(), p, avail);
        }
        p = buf.get();
        while (avail < need && !eof) {
            // a file's first read need not fill the whole buffer: bulk reads go straight to the caller
            const std::size_t want = std::min(buf_size - avail, std::max(need - avail, kChunk));
            const std::size_t got = read_some(buf.get() + avail, want);
            avail += got;
            if (got == 0) eof = true;
        }
        return avail >= need;
    }
    /// One read(2) (what a pipe has now, or up to n bytes of a file); 0 at the end.
    std::size_t read_some(std::byte* dst, std::size_t n) {
        for (;;) {
            const ssize_t got = ::read(fd, dst, n);
            if (got >= 0) return static_cast<std::size_t>(got);
            if (errno != EINTR) throw IoError(name + ": read failed: " + std::strerror(errno));
        }
    }
    void consume(std::size_t n) {
        p += n;
        avail -= n;
        offset += n;
    }
    /// Bytes left after the window's start, when known.
    bool remaining(std::uint64_t& r) const {
        if (!size_known) return false;
        r = total >= offset ? total - offset : 0;
        return true;
    }

    const PlyElement& E() const { return h.elements[elem]; }

    FormatError truncated() const {
        return FormatError(at() + "truncated PLY body in element '" + ply_escape(E().name) + "' at record " +
                           std::to_string(rec) + " of " + std::to_string(E().count));
    }

    void open_header() {
        // grow the window until it holds the end_header line (or the limit, or the end)
        for (std::size_t need = 4096;; need = std::min(need * 4, kPlyMaxHeaderBytes)) {
            fill(need);
            const std::string_view t(reinterpret_cast<const char*>(p), avail);
            if (t.substr(0, 3) != "ply" || t.find("\nend_header\n") != std::string_view::npos ||
                t.find("\nend_header\r\n") != std::string_view::npos || eof || need >= kPlyMaxHeaderBytes)
                break;
        }
        const std::string_view text(reinterpret_cast<const char*>(p), std::min(avail, kPlyMaxHeaderBytes));
        h = parse_ply_header(text, name);
        consume(h.header_bytes);
        ascii = h.encoding == PlyEncoding::ascii;
        swap = !ascii && ((h.encoding == PlyEncoding::binary_big_endian) == (std::endian::native == std::endian::little));
        line = h.header_lines;
        // the smallest body the header implies must fit in what follows it
        std::uint64_t left = 0;
        if (remaining(left)) {
            std::uint64_t need = 0;
            for (const auto& e : h.elements) {
                const std::uint64_t per = ascii ? 2 * e.props.size() : e.min_record_bytes();
                if (!mul_add(need, e.count, per))
                    throw FormatError(name + ": line " + std::to_string(e.line) + ": PLY element '" + ply_escape(e.name) +
                                      "' count " + std::to_string(e.count) + " x " + std::to_string(per) +
                                      " bytes per record overflows");
                if (ascii ? need > left + 1 : need > left)
                    throw FormatError(name + ": line " + std::to_string(e.line) + ": PLY element '" + ply_escape(e.name) +
                                      "' claims " + std::to_string(e.count) + " records (with the elements before it at least " +
                                      std::to_string(need) + " bytes) but only " + std::to_string(left) +
                                      " bytes follow the header");
            }
        }
        settle();
    }
    /// Moves past elements whose records are all read.
    void settle() {
        while (elem < h.elements.size() && rec == h.elements[elem].count) ++elem, rec = 0;
    }

    // ---- ASCII --------------------------------------------------------------------------------
    /// The next non-blank line's tokens; false at the end of the input.
    bool next_line() {
        for (;;) {
            std::size_t scanned = 0;
            const void* q = nullptr;
            for (;;) {
                if (avail > scanned) q = std::memchr(p + scanned, '\n', avail - scanned);
                if (q || eof) break;
                scanned = avail;
                if (avail >= kMaxLine) throw FormatError(at() + "PLY line longer than " + std::to_string(kMaxLine) + " bytes");
                fill(avail + 1);
            }
            const std::size_t nl = q ? static_cast<std::size_t>(static_cast<const std::byte*>(q) - p) : avail;
            if (avail == 0) return false;
            const std::string_view l(reinterpret_cast<const char*>(p), nl);
            ++line;
            tok.clear();
            tok_i = 0;
            std::size_t i = 0;
            while (i < l.size()) {
                while (i < l.size() && (l[i] == ' ' || l[i] == '\t' || l[i] == '\r' || l[i] == '\f' || l[i] == '\v')) ++i;
                const std::size_t b = i;
                while (i < l.size() && l[i] != ' ' && l[i] != '\t' && l[i] != '\r' && l[i] != '\f' && l[i] != '\v') ++i;
                if (i > b) tok.push_back(l.substr(b, i - b));
            }
            line_bytes = std::min(nl + 1, avail);
            if (!tok.empty()) return true;
            consume(line_bytes);
        }
    }
    std::size_t line_bytes = 0;
    /// Releases the line's bytes (tokens are views into them).
    void end_line() {
        if (tok_i != tok.size())
            throw FormatError(at() + std::to_string(tok.size()) + " values for a '" + ply_escape(E().name) +
                              "' record, expected " + std::to_string(tok_i));
        consume(line_bytes);
        tok.clear();
        tok_i = 0;
    }
    double ascii_value(StoredType t, const std::string& prop) {
        if (tok_i >= tok.size())
            throw FormatError(at() + std::to_string(tok.size()) + " values for a '" + ply_escape(E().name) +
                              "' record, more expected (property '" + ply_escape(prop) + "')");
        std::string_view s = tok[tok_i++];
        std::string_view num = s;
        if (num.size() > 1 && num[0] == '+' && num[1] != '-') num.remove_prefix(1);
        double v = 0;
        const auto r = std::from_chars(num.data(), num.data() + num.size(), v);
        if (r.ec == std::errc::result_out_of_range && r.ptr == num.data() + num.size()) {
            v = std::strtod(std::string(num).c_str(), nullptr);  // denormal or huge: strtod's nearest
        } else if (r.ec != std::errc() || r.ptr != num.data() + num.size()) {
            throw FormatError(at() + "bad number '" + ply_escape(s) + "' for property '" + ply_escape(prop) + "'");
        }
        if (t == StoredType::f32) return static_cast<float>(v);  // the value a float property holds
        if (t != StoredType::f64) {
            double lo, hi;
            int_range(t, lo, hi);
            if (!(v >= lo && v <= hi) || v != std::floor(v))
                throw FormatError(at() + "'" + ply_escape(s) + "' is not a " + ply_type_name(t) + " (property '" +
                                  ply_escape(prop) + "')");
        }
        return v;
    }

    // ---- records ------------------------------------------------------------------------------
    std::vector<int> all_columns;
    std::vector<std::size_t> col_off;

    std::size_t read_values(std::vector<double>& out, std::size_t max, std::span<const int> columns) {
        settle();
        if (elem >= h.elements.size()) {
            out.clear();
            return 0;
        }
        const PlyElement& e = E();
        if (e.has_lists())
            throw FormatError(name + ": PLY element '" + ply_escape(e.name) + "' has list properties (read it by records)");
        const std::size_t np = e.props.size();
        if (columns.empty()) {
            all_columns.resize(np);
            for (std::size_t k = 0; k < np; ++k) all_columns[k] = static_cast<int>(k);
            columns = all_columns;
        }
        for (int c : columns)
            if (c < 0 || static_cast<std::size_t>(c) >= np) throw std::invalid_argument(name + ": PLY column out of range");
        const std::size_t nc = columns.size();
        // at most 32 MiB of values per call, whatever `max` and the header say
        const std::size_t cap = std::max<std::size_t>(1, (std::size_t(32) << 20) / (sizeof(double) * std::max<std::size_t>(nc, 1)));
        const std::size_t n = static_cast<std::size_t>(std::min<std::uint64_t>(std::min(max, cap), e.count - rec));
        out.resize(n * nc);
        if (ascii) {
            std::vector<double> vals(np);
            for (std::size_t i = 0; i < n; ++i) {
                if (!next_line()) throw truncated();
                for (std::size_t k = 0; k < np; ++k) vals[k] = ascii_value(e.props[k].type, e.props[k].name);
                end_line();
                ++rec;
                for (std::size_t c = 0; c < nc; ++c) out[i * nc + c] = vals[columns[c]];
            }
        } else {
            const std::size_t rs = e.min_record_bytes();
            col_off.assign(np, 0);
            for (std::size_t k = 1; k < np; ++k) col_off[k] = col_off[k - 1] + stored_size(e.props[k - 1].type);
            std::size_t i = 0;
            while (i < n) {
                if (!fill(rs)) throw truncated();
                const std::size_t k = std::min(n - i, avail / rs);  // whole records in the window
                for (std::size_t c = 0; c < nc; ++c)
                    decode_column(p + col_off[columns[c]], rs, k, e.props[columns[c]].type, &out[i * nc + c], nc);
                consume(k * rs);
                rec += k;
                i += k;
            }
        }
        settle();
        return n;
    }

    /// k values of type t, `stride` bytes apart, into dst[0], dst[step], ...
    void decode_column(const std::byte* src, std::size_t stride, std::size_t k, StoredType t, double* dst, std::size_t step) {
        auto run = [&](auto tag) {
            using T = decltype(tag);
            for (std::size_t r = 0; r < k; ++r) {
                unsigned char b[sizeof(T)];
                std::memcpy(b, src + r * stride, sizeof(T));
                if (swap) std::reverse(b, b + sizeof(T));
                T v;
                std::memcpy(&v, b, sizeof(T));
                dst[r * step] = static_cast<double>(v);
            }
        };
        switch (t) {
            case StoredType::i8: run(std::int8_t{}); break;
            case StoredType::u8: run(std::uint8_t{}); break;
            case StoredType::i16: run(std::int16_t{}); break;
            case StoredType::u16: run(std::uint16_t{}); break;
            case StoredType::i32: run(std::int32_t{}); break;
            case StoredType::u32: run(std::uint32_t{}); break;
            case StoredType::f32: run(float{}); break;
            default: run(double{}); break;
        }
    }

    std::size_t read_raw(std::byte* dst, std::size_t max) {
        settle();
        if (elem >= h.elements.size()) return 0;
        const PlyElement& e = E();
        if (ascii || e.has_lists())
            throw FormatError(name + ": PLY element '" + ply_escape(e.name) + "' is not stored as fixed-size binary records");
        const std::size_t rs = e.min_record_bytes();
        const std::size_t n = static_cast<std::size_t>(std::min<std::uint64_t>(max, e.count - rec));
        std::size_t want = n * rs, got = std::min(want, avail);
        std::memcpy(dst, p, got);
        consume(got);
        while (got < want && fd >= 0 && !eof) {  // the rest straight into dst
            const std::size_t more = read_some(dst + got, want - got);
            got += more;
            offset += more;
            if (more == 0) eof = true;
        }
        if (got < want) {
            rec += got / rs;
            throw truncated();
        }
        rec += n;
        settle();
        return n;
    }

    bool read_record(PlyRecord& r) {
        settle();
        if (elem >= h.elements.size()) return false;
        const PlyElement& e = E();
        const std::size_t np = e.props.size();
        r.values.assign(np, 0.0);
        r.lists.resize(np);
        for (auto& l : r.lists) l.clear();
        if (ascii && !next_line()) throw truncated();
        for (std::size_t k = 0; k < np; ++k) {
            const PlyProperty& pr = e.props[k];
            const StoredType t = pr.is_list ? pr.count_type : pr.type;
            double v;
            if (ascii) {
                v = ascii_value(t, pr.name);
            } else {
                if (!fill(stored_size(t))) throw truncated();
                v = decode(p, t, swap);
                consume(stored_size(t));
            }
            if (!pr.is_list) {
                r.values[k] = v;
                continue;
            }
            if (v < 0) throw FormatError(at() + "negative list length " + std::to_string(static_cast<long long>(v)) +
                                         " in element '" + ply_escape(e.name) + "'");
            const auto c = static_cast<std::uint64_t>(v);
            const std::size_t is = stored_size(pr.type);
            if (ascii) {
                if (c > tok.size() - tok_i)
                    throw FormatError(at() + "list of " + std::to_string(c) + " items, the line has " +
                                      std::to_string(tok.size() - tok_i) + " values left");
                r.lists[k].reserve(c);
                for (std::uint64_t q = 0; q < c; ++q) r.lists[k].push_back(ascii_value(pr.type, pr.name));
            } else {
                std::uint64_t left = 0;
                if (remaining(left) && c * is > left) throw truncated();
                for (std::uint64_t q = 0; q < c; ++q) {
                    if (!fill(is)) throw truncated();
                    r.lists[k].push_back(decode(p, pr.type, swap));
                    consume(is);
                }
            }
        }
        if (ascii) end_line();
        ++rec;
        settle();
        return true;
    }

    void skip_to(std::size_t target) {
        if (target > h.elements.size()) target = h.elements.size();
        settle();
        for (std::size_t e = target; e < elem; ++e)  // passed empty elements are fine
            if (h.elements[e].count) throw std::logic_error(name + ": PLY reader cannot go back to an earlier element");
        std::vector<double> vals;
        PlyRecord r;
        while (elem < target) {
            const PlyElement& e = E();
            if (!ascii && !e.has_lists()) {
                const std::size_t rs = e.min_record_bytes();
                std::uint64_t bytes;  // checked at open when the size is known; saturates for pipes
                if (__builtin_mul_overflow(e.count - rec, static_cast<std::uint64_t>(rs), &bytes))
                    bytes = std::numeric_limits<std::uint64_t>::max();
                while (bytes) {
                    if (!fill(1)) throw truncated();
                    const std::size_t k = static_cast<std::size_t>(std::min<std::uint64_t>(bytes, avail));
                    consume(k);
                    bytes -= k;
                }
                rec = e.count;
                settle();
            } else if (!e.has_lists()) {
                read_values(vals, 65536, {});
            } else {
                read_record(r);
            }
        }
    }

    std::uint64_t finish(bool allow_trailing) {
        skip_to(h.elements.size());
        std::uint64_t trailing = 0;
        if (ascii) {
            ++line;  // the position is at the start of the line after the last record
            bool seen = false;  // trailing = bytes from the first non-whitespace one on
            while (fill(1)) {
                for (std::size_t i = 0; i < avail && !seen; ++i) {
                    const char c = static_cast<char>(p[i]);
                    if (c == '\n') ++line;
                    if (c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\f' || c == '\v') continue;
                    if (!allow_trailing)
                        throw FormatError(at() + "unexpected '" +
                                          ply_escape(std::string_view(reinterpret_cast<const char*>(p + i),
                                                                      std::min<std::size_t>(avail - i, 16))) +
                                          "' after the last PLY element");
                    seen = true;
                    trailing -= i;  // the whitespace before it is not trailing data
                }
                if (seen) trailing += avail;
                consume(avail);
            }
            return trailing;
        }
        while (fill(1)) {
            trailing += avail;
            if (!allow_trailing)
                throw FormatError(at() + (size_known ? std::to_string(total - offset) : std::string("some")) +
                                  " trailing bytes after the last PLY element");
            consume(avail);
        }
        return trailing;
    }
};

PlyReader::PlyReader(const std::string& path) : d_(std::make_unique<Impl>()) {
    Impl& d = *d_;
    d.name = path;
    struct stat st{};
    if (::stat(path.c_str(), &st) != 0) throw IoError(path + ": cannot open: " + std::strerror(errno));
    if (S_ISDIR(st.st_mode)) throw IoError(path + ": is a directory, expected a PLY file");
    d.fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (d.fd < 0) throw IoError(path + ": cannot open: " + std::strerror(errno));
    if (S_ISREG(st.st_mode)) {
        d.size_known = true;
        d.total = static_cast<std::uint64_t>(st.st_size);
    }
    d.buf.reset(new std::byte[kBuffer]);
    d.buf_size = kBuffer;
    d.p = d.buf.get();
    d.open_header();
}

PlyReader::PlyReader(std::string name, std::span<const std::byte> bytes) : d_(std::make_unique<Impl>()) {
    Impl& d = *d_;
    d.name = std::move(name);
    d.p = bytes.data();
    d.avail = bytes.size();
    d.eof = true;
    d.size_known = true;
    d.total = bytes.size();
    d.open_header();
}

PlyReader::~PlyReader() = default;

const PlyHeader& PlyReader::header() const { return d_->h; }
const std::string& PlyReader::name() const { return d_->name; }
std::size_t PlyReader::element() const {
    d_->settle();
    return d_->elem;
}
std::uint64_t PlyReader::record() const { return d_->rec; }
void PlyReader::skip_to(std::size_t e) { d_->skip_to(e); }
std::size_t PlyReader::read_values(std::vector<double>& out, std::size_t max, std::span<const int> columns) {
    return d_->read_values(out, max, columns);
}
std::size_t PlyReader::read_raw(std::byte* dst, std::size_t max) { return d_->read_raw(dst, max); }
bool PlyReader::read_record(PlyRecord& r) { return d_->read_record(r); }
std::uint64_t PlyReader::finish(bool allow_trailing) { return d_->finish(allow_trailing); }
bool PlyReader::size_known() const { return d_->size_known; }
std::string PlyReader::where() const { return d_->at(); }

}  // namespace meshless
