#include "formats/point_stream.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zstd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <memory>
#include <sstream>

#include "kernels/significant_text.hpp"
#include "formats/crc32.hpp"
#include "formats/text_header.hpp"
#include "kernels/errors.hpp"

namespace meshless {

namespace {

constexpr unsigned char kMagic[8] = {0x89, 'M', 'L', 'S', '\r', '\n', 0x1a, '\n'};
constexpr std::uint32_t kFrameMeta = 1, kFrameData = 2, kFrameEnd = 3;
constexpr std::uint32_t kFlagZstd = 1, kFlagCells = 2;
constexpr std::uint32_t kMaxPayload = 1u << 30;
// Frame payloads up to this size are read (or decompressed) straight into the caller's records;
// larger claims are first proven by the data (StreamReader::read_proven / decompress_proven). The
// writers' frames hold at most kMaxBatchRecords = 65,536 records (5.5 MiB of 88-byte samples, 2 MiB
// of points): all below it.
constexpr std::size_t kProvenBytes = std::size_t{8} << 20;

void put_u32(unsigned char* p, std::uint32_t v) {
    for (int i = 0; i < 4; ++i) p[i] = static_cast<unsigned char>(v >> (8 * i));
}
void put_u64(unsigned char* p, std::uint64_t v) {
    for (int i = 0; i < 8; ++i) p[i] = static_cast<unsigned char>(v >> (8 * i));
}
std::uint32_t get_u32(const unsigned char* p) {
    std::uint32_t v = 0;
    for (int i = 3; i >= 0; --i) v = (v << 8) | p[i];
    return v;
}
std::uint64_t get_u64(const unsigned char* p) {
    std::uint64_t v = 0;
    for (int i = 7; i >= 0; --i) v = (v << 8) | p[i];
    return v;
}
std::uint32_t crc_of(const void* p, std::size_t n) { return crc32_ieee(0, p, n); }
std::string hex(std::uint32_t v) {
    char buf[16];
    std::snprintf(buf, sizeof buf, "%x", v);
    return buf;
}

/// A pipe's buffer grown to 1 MiB (Linux F_SETPIPE_SZ; the default 64 KiB makes the stages of a
/// pipeline wake each other ~16 times per megabyte). Not a pipe, or refused: left as it is.
void widen_pipe(std::FILE* f) {
#ifdef F_SETPIPE_SZ
    struct stat st {};
    const int fd = fileno(f);
    if (fd >= 0 && ::fstat(fd, &st) == 0 && S_ISFIFO(st.st_mode) && ::fcntl(fd, F_GETPIPE_SZ) < (1 << 20))
        (void)::fcntl(fd, F_SETPIPE_SZ, 1 << 20);
#else
    (void)f;
#endif
}

}  // namespace

std::size_t record_size(RecordKind k, std::uint32_t flags) {
    switch (k) {
        case RecordKind::point: return (flags & kStreamFlagBlocks) ? kPointBlockRecordSize : sizeof(PointRecord);
        case RecordKind::sample: return sizeof(SampleRecord);
        case RecordKind::seed: return sizeof(SeedRecord);
        case RecordKind::mesh:
        case RecordKind::query: break;
    }
    throw InvalidArgument("point stream: record kind " + std::to_string(static_cast<std::uint32_t>(k)) + " has no stream form");
}

void interleave_point_blocks(const PointRecord* points, const std::uint32_t* blocks, std::size_t n, std::vector<char>& out) {
    out.resize(n * kPointBlockRecordSize);
    char* p = out.data();
    for (std::size_t i = 0; i < n; ++i, p += kPointBlockRecordSize) {
        std::memcpy(p, &points[i], sizeof(PointRecord));
        std::memcpy(p + sizeof(PointRecord), &blocks[i], sizeof(std::uint32_t));
    }
}

void deinterleave_point_blocks(const char* records, std::size_t n, std::vector<PointRecord>& points,
                               std::vector<std::uint32_t>& blocks) {
    points.resize(n);
    blocks.resize(n);
    for (std::size_t i = 0; i < n; ++i, records += kPointBlockRecordSize) {
        std::memcpy(&points[i], records, sizeof(PointRecord));
        std::memcpy(&blocks[i], records + sizeof(PointRecord), sizeof(std::uint32_t));
    }
}

void StreamMeta::set(const std::string& k, const std::string& v) { kv[k] = line_breaks_escaped(v); }

void StreamMeta::set(const std::string& k, double v) { kv[k] = significant_text(v, 17); }

std::optional<std::string> StreamMeta::get(const std::string& k) const {
    auto it = kv.find(k);
    if (it == kv.end()) return std::nullopt;
    return it->second;
}

std::optional<double> StreamMeta::get_double(const std::string& k) const {
    auto s = get(k);
    if (!s) return std::nullopt;
    char* end = nullptr;
    const double v = std::strtod(s->c_str(), &end);
    if (end == s->c_str() || *end != '\0')
        throw FormatError(where() + "stream metadata: '" + escape_field(k) + "' is not a number: " +
                          escape_field(*s));
    return v;
}

std::optional<double> StreamMeta::get_finite(const std::string& k) const {
    const auto v = get_double(k);
    if (v && !std::isfinite(*v))
        throw FormatError(where() + "stream metadata: '" + escape_field(k) +
                          "' is not a finite number: " + escape_field(*get(k)));
    return v;
}

std::string StreamMeta::serialize() const {
    std::string out;
    for (const auto& [k, v] : kv) {
        out += k;
        out += '=';
        for (char c : v) out += (c == '\n' ? ' ' : c);
        out += '\n';
    }
    return out;
}

StreamMeta StreamMeta::parse(const std::string& text, const std::string& name) {
    StreamMeta m;
    std::istringstream in(text);
    std::string line;
    while (std::getline(in, line)) {
        if (line.empty()) continue;
        auto eq = line.find('=');
        if (eq == std::string::npos) throw FormatError(name + ": malformed META frame line '" + escape_field(line) + "'");
        m.kv[line.substr(0, eq)] = line.substr(eq + 1);
    }
    return m;
}

// ---------------------------------------------------------------- writer

StreamWriter::StreamWriter(std::FILE* f, std::string name, RecordKind kind, bool compress, std::uint32_t flags)
    : f_(f), name_(std::move(name)), rsize_(record_size(kind, flags)), compress_(compress) {
    if ((flags & ~kStreamFlagBlocks) != 0 || ((flags & kStreamFlagBlocks) && kind != RecordKind::point))
        throw InvalidArgument(name_ + ": stream flags " + std::to_string(flags) + " are not valid for this record kind");
    widen_pipe(f_);
    unsigned char h[32] = {};
    std::memcpy(h, kMagic, 8);
    put_u32(h + 8, kStreamVersion);
    put_u32(h + 12, static_cast<std::uint32_t>(kind));
    put_u32(h + 16, static_cast<std::uint32_t>(rsize_));
    put_u32(h + 20, flags);
    put(h, sizeof h);
}

void StreamWriter::put(const void* p, std::size_t n) {
    if (n && std::fwrite(p, 1, n, f_) != n) {
        if (errno == EPIPE) throw BrokenPipe();
        throw IoError(name_ + ": write failed (" + std::strerror(errno) + ")");
    }
}

void StreamWriter::write_frame(std::uint32_t type, std::uint32_t flags, std::uint64_t seq,
                               std::uint64_t count, const void* payload, std::uint32_t bytes) {
    unsigned char h[32];
    put_u32(h, type);
    put_u32(h + 4, flags);
    put_u64(h + 8, seq);
    put_u64(h + 16, count);
    put_u32(h + 24, bytes);
    put_u32(h + 28, crc_of(payload, bytes));
    put(h, sizeof h);
    put(payload, bytes);
}

void StreamWriter::write_meta(const StreamMeta& m) {
    const std::string s = m.serialize();
    write_frame(kFrameMeta, 0, 0, 0, s.data(), static_cast<std::uint32_t>(s.size()));
}

void StreamWriter::write_segment(std::uint64_t index, const StreamMeta& keys) {
    StreamMeta m = keys;
    m.kv["segment"] = std::to_string(index);
    write_meta(m);
}

void StreamWriter::index_cells(const CellGrid& grid, SampleCellEncoder::Verify verify) {
    if (rsize_ == sizeof(SampleRecord) && !compress_) cells_.emplace(grid, verify);
}

void StreamWriter::write_data(std::uint64_t seq, const void* records, std::uint64_t count) {
    if (count == 0) return;
    if (count > kMaxPayload / rsize_) throw FormatError(name_ + ": batch of " + std::to_string(count) + " records too large for one frame");
    const std::size_t raw = count * rsize_;
    if (raw > kMaxPayload) throw FormatError(name_ + ": batch of " + std::to_string(count) + " records too large for one frame");
    if (cells_ && cells_->encode(static_cast<const SampleRecord*>(records), static_cast<std::size_t>(count), scratch_)) {
        write_frame(kFrameData, kFlagCells, seq, count, scratch_.data(), static_cast<std::uint32_t>(scratch_.size()));
    } else if (compress_) {
        scratch_.resize(ZSTD_compressBound(raw));
        const std::size_t n = ZSTD_compress(scratch_.data(), scratch_.size(), records, raw, 1);
        if (ZSTD_isError(n)) throw IoError(name_ + ": zstd compression failed");
        write_frame(kFrameData, kFlagZstd, seq, count, scratch_.data(), static_cast<std::uint32_t>(n));
    } else {
        write_frame(kFrameData, 0, seq, count, records, static_cast<std::uint32_t>(raw));
    }
    total_ += count;
}

void StreamWriter::finish() {
    write_frame(kFrameEnd, 0, 0, total_, nullptr, 0);
    if (std::fflush(f_) != 0) {
        if (errno == EPIPE) throw BrokenPipe();
        throw IoError(name_ + ": write failed (" + std::strerror(errno) + ")");
    }
}

// ---------------------------------------------------------------- reader

bool StreamReader::read_exact(void* p, std::size_t n) {
    const std::size_t got = std::fread(p, 1, n, f_);
    if (got == n) return true;
    if (std::ferror(f_)) throw IoError(name_ + ": read failed (" + std::strerror(errno) + ")");
    if (got == 0) return false;
    throw FormatError(name_ + ": truncated stream (EOF inside a frame after " + std::to_string(total_) + " records)");
}

void StreamReader::read_proven(std::vector<char>& buf, std::size_t bytes) {
    buf.clear();
    std::size_t have = 0;
    while (have < bytes) {
        const std::size_t want = std::min(bytes, std::max(kProvenBytes, 2 * have));
        buf.resize(want);
        const std::size_t got = std::fread(buf.data() + have, 1, want - have, f_);
        if (got != want - have) {
            if (std::ferror(f_)) throw IoError(name_ + ": read failed (" + std::strerror(errno) + ")");
            throw FormatError(name_ + ": truncated stream (EOF inside a frame after " + std::to_string(total_) + " records)");
        }
        have = want;
    }
}

void StreamReader::decompress_proven(const std::vector<char>& in, std::size_t raw, std::vector<char>& buf) {
    const auto corrupt = [&] {
        return FormatError(name_ + ": corrupt compressed frame after " + std::to_string(total_) + " records");
    };
    const std::unique_ptr<ZSTD_DCtx, std::size_t (*)(ZSTD_DCtx*)> ctx(ZSTD_createDCtx(), ZSTD_freeDCtx);
    if (!ctx) throw std::bad_alloc();
    ZSTD_inBuffer src{in.data(), in.size(), 0};
    buf.clear();
    std::size_t have = 0;
    for (;;) {
        if (have == buf.size()) {
            if (have == raw) {
                // full: the frame must end here, without another byte to give
                char extra;
                ZSTD_outBuffer one{&extra, 1, 0};
                const std::size_t r = ZSTD_decompressStream(ctx.get(), &one, &src);
                if (ZSTD_isError(r) || one.pos != 0 || r != 0 || src.pos != src.size) throw corrupt();
                return;
            }
            buf.resize(std::min(raw, std::max(kProvenBytes, 2 * have)));
        }
        ZSTD_outBuffer dst{buf.data(), buf.size(), have};
        const std::size_t r = ZSTD_decompressStream(ctx.get(), &dst, &src);
        if (ZSTD_isError(r)) throw corrupt();
        const bool progressed = dst.pos != have;
        have = dst.pos;
        if (r == 0 || (!progressed && src.pos == src.size)) {
            if (r != 0 || have != raw || src.pos != src.size) throw corrupt();  // ended early, or bytes after the frame
            buf.resize(have);
            return;
        }
    }
}

StreamReader::StreamReader(std::FILE* f, std::string name) : f_(f), name_(std::move(name)) {
    widen_pipe(f_);
    unsigned char h[32];
    const std::size_t got = std::fread(h, 1, sizeof h, f_);
    if (got == 0) throw FormatError(name_ + ": empty input, expected a meshless point stream");
    if (got < 8 || std::memcmp(h, kMagic, 8) != 0) {
        // name what it looks like instead: the usual mistake is a file meant for another command
        const std::string_view head(reinterpret_cast<const char*>(h), got);
        std::string hint;
        if (head.substr(0, 4) == "ply\n" || head.substr(0, 5) == "ply\r\n")
            hint = "; it is a PLY file: give its path (PLY point sets are read from files)";
        else if (head.substr(0, 5) == "<?xml" || head.substr(0, 8) == "<VTKFile")
            hint = "; it is an XML (VTK) file: give its path to a command that reads it";
        throw FormatError(name_ + ": not a meshless point stream (starts \"" + escape_field(head.substr(0, 12), 12) + "\")" +
                          hint);
    }
    if (got < sizeof h) throw FormatError(name_ + ": truncated stream header");
    const std::uint32_t version = get_u32(h + 8);
    if (version != kStreamVersion)
        throw FormatError(name_ + ": stream version " + std::to_string(version) + " is not supported (this build reads version " +
                          std::to_string(kStreamVersion) + ")");
    const std::uint32_t kind = get_u32(h + 12), rsize = get_u32(h + 16);
    flags_ = get_u32(h + 20);
    if (kind != 1 && kind != 2 && kind != 5) throw FormatError(name_ + ": unknown record kind " + std::to_string(kind));
    kind_ = static_cast<RecordKind>(kind);
    if ((flags_ & ~kStreamFlagBlocks) != 0)
        throw FormatError(name_ + ": unknown stream header flags 0x" + hex(flags_) + " (written by a newer version?)");
    if ((flags_ & kStreamFlagBlocks) && kind_ != RecordKind::point)
        throw FormatError(name_ + ": block ids flagged on a stream of kind " + std::to_string(kind) + " (only points carry them)");
    rsize_ = record_size(kind_, flags_);
    if (rsize != rsize_)
        throw FormatError(name_ + ": record size " + std::to_string(rsize) + " does not match kind " + std::to_string(kind) +
                          " (expected " + std::to_string(rsize_) + ")");
}

void StreamReader::read_meta() {
    if (pending_ || ended_) return;
    pending_buf_.clear();
    if (auto n = next_data(pending_buf_)) {
        pending_ = true;
        pending_count_ = *n;
    }
}

std::optional<std::uint64_t> StreamReader::next_data(std::vector<char>& out) {
    return next_records([&](std::uint64_t count) -> void* {
        const std::size_t at = out.size();
        out.resize(at + count * rsize_);
        return out.data() + at;
    });
}

std::optional<StreamMeta> StreamReader::next_segment() {
    if (at_segment_) {
        at_segment_ = false;
        return segment_;
    }
    if (pending_ || (!ended_ && next_records([&](std::uint64_t) -> void* {
                        throw FormatError(name_ + ": records outside a segment (after " + std::to_string(total_) +
                                          " records) in a stream of segments");
                    })))
        throw FormatError(name_ + ": records before the first segment frame in a stream of segments");
    if (at_segment_) return next_segment();
    return std::nullopt;
}

std::optional<std::uint64_t> StreamReader::next_records(const std::function<void*(std::uint64_t count)>& room) {
    if (at_segment_) return std::nullopt;
    if (pending_) {
        pending_ = false;
        void* dst = room(pending_count_);
        if (!pending_buf_.empty()) std::memcpy(dst, pending_buf_.data(), pending_buf_.size());
        return pending_count_;
    }
    if (ended_) return std::nullopt;
    const std::size_t rsize = rsize_;
    for (;;) {
        unsigned char h[32];
        if (!read_exact(h, sizeof h))
            throw FormatError(name_ + ": truncated stream (no END frame after " + std::to_string(total_) + " records)");
        const std::uint32_t type = get_u32(h), flags = get_u32(h + 4);
        const std::uint64_t count = get_u64(h + 16);
        const std::uint32_t bytes = get_u32(h + 24), crc = get_u32(h + 28);
        if (bytes > kMaxPayload) throw FormatError(name_ + ": corrupt frame header (payload of " + std::to_string(bytes) + " bytes)");
        const auto truncated = [&] {
            return FormatError(name_ + ": truncated stream (EOF inside a frame after " + std::to_string(total_) + " records)");
        };
        const auto bad_crc = [&] {
            return FormatError(name_ + ": frame checksum mismatch after " + std::to_string(total_) + " records (corrupt stream)");
        };
        if (type == kFrameData && (flags & ~(kFlagZstd | kFlagCells)) != 0)
            throw FormatError(name_ + ": DATA frame with unknown flags 0x" + hex(flags) + " after " + std::to_string(total_) +
                              " records (written by a newer version?)");
        if (type == kFrameData && flags == (kFlagZstd | kFlagCells))
            throw FormatError(name_ + ": DATA frame flagged both zstd and cell-indexed after " + std::to_string(total_) + " records");
        if (type == kFrameData && flags == kFlagCells && kind_ != RecordKind::sample)
            throw FormatError(name_ + ": cell-indexed DATA frame in a stream of kind " +
                              std::to_string(static_cast<std::uint32_t>(kind_)) + " (only samples are)");
        if (type == kFrameData && flags == 0) {
            // raw records: read straight into the caller's room, checksummed there (no copy)
            if (count > kMaxPayload / rsize) throw FormatError(name_ + ": corrupt frame header (" + std::to_string(count) + " records)");
            if (bytes != count * rsize)
                throw FormatError(name_ + ": DATA frame of " + std::to_string(count) + " records has " + std::to_string(bytes) + " bytes");
            if (bytes > kProvenBytes) {  // a large claim: proven by the data before the records take it
                read_proven(staged_, bytes);
                if (crc_of(staged_.data(), bytes) != crc) throw bad_crc();
                std::memcpy(room(count), staged_.data(), bytes);
                staged_.clear();
            } else {
                void* dst = room(count);
                if (bytes && !read_exact(dst, bytes)) throw truncated();
                if (crc_of(dst, bytes) != crc) throw bad_crc();
            }
            total_ += count;
            data_bytes_ += bytes;
            return count;
        }
        if (bytes > kProvenBytes) {
            read_proven(stored_, bytes);
        } else {
            stored_.resize(bytes);
            if (bytes && !read_exact(stored_.data(), bytes)) throw truncated();
        }
        if (crc_of(stored_.data(), bytes) != crc) throw bad_crc();
        if (type == kFrameEnd) {
            if (count != total_)
                throw FormatError(name_ + ": END frame says " + std::to_string(count) + " records, stream held " + std::to_string(total_));
            ended_ = true;
            // a stream is one header ... END; bytes after it (two streams concatenated, a
            // corrupted tail) would otherwise be dropped without a word
            if (std::fgetc(f_) != EOF)
                throw FormatError(name_ + ": unexpected data after the END frame (concatenated or corrupt stream)");
            return std::nullopt;
        }
        if (type == kFrameMeta) {
            StreamMeta m = StreamMeta::parse(std::string(stored_.begin(), stored_.end()), name_);
            if (const auto seg = m.get("segment")) {
                if (*seg != std::to_string(segments_))
                    throw FormatError(name_ + ": segment frame '" + escape_field(*seg) + "' where segment " + std::to_string(segments_) +
                                      " was due (after " + std::to_string(total_) + " records)");
                ++segments_;
                m.source = name_;
                segment_ = std::move(m);
                if (!stop_at_segments_) continue;
                at_segment_ = true;
                return std::nullopt;
            }
            for (const auto& [k, v] : m.kv) meta_.kv[k] = v;
            meta_.source = name_;
            continue;
        }
        if (type != kFrameData) continue;  // unknown frame type: skip
        if (count > kMaxPayload / rsize) throw FormatError(name_ + ": corrupt frame header (" + std::to_string(count) + " records)");
        if (flags == kFlagCells) {
            // the payload is read and checksummed: its size must be exactly what its header implies
            // for `count` records before room() takes memory for them
            try {
                SampleCellDecoder::check(stored_.data(), bytes, count);
                cells_.decode(stored_.data(), bytes, count, static_cast<SampleRecord*>(room(count)));
            } catch (const FormatError& e) {
                throw FormatError(name_ + ": " + e.what() + " (after " + std::to_string(total_) + " records)");
            }
            total_ += count;
            data_bytes_ += bytes;
            ++cell_frames_;
            return count;
        }
        const std::size_t raw = count * rsize;
        if (raw > kProvenBytes) {  // a large claim: decompressed (proven) before the records take it
            decompress_proven(stored_, raw, staged_);
            std::memcpy(room(count), staged_.data(), raw);
            staged_.clear();
        } else {
            void* dst = room(count);
            const std::size_t n = ZSTD_decompress(dst, raw, stored_.data(), bytes);
            if (ZSTD_isError(n) || n != raw) throw FormatError(name_ + ": corrupt compressed frame after " + std::to_string(total_) + " records");
        }
        total_ += count;
        data_bytes_ += bytes;
        return count;
    }
}

}  // namespace meshless
