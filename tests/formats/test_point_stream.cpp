// The on-pipe stream codec: round trips and every must-fail input (garbage, wrong version, wrong
// record size, truncation at every byte, flipped bits, wrong END totals).
#include <catch2/catch.hpp>

#include <unistd.h>

#include <csignal>
#include <cstdio>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

#include "formats/point_stream.hpp"
#include "kernels/errors.hpp"

using namespace meshless;

namespace {

std::vector<PointRecord> some_points(int n, int seed) {
    std::vector<PointRecord> v(n);
    for (int i = 0; i < n; ++i)
        for (int a = 0; a < 3; ++a) {
            v[i].pos[a] = static_cast<float>(seed * 1000 + i * 3 + a);
            v[i].normal[a] = a == 2 ? 1.0f : 0.0f;
            v[i].radius = 0.5f;
            v[i].value = static_cast<float>(i);
        }
    return v;
}

/// Encodes batches into an in-memory stream.
std::string encode(const std::vector<std::vector<PointRecord>>& batches, bool compress, StreamMeta meta = {}) {
    char* buf = nullptr;
    std::size_t len = 0;
    std::FILE* f = open_memstream(&buf, &len);
    {
        StreamWriter w(f, "mem", RecordKind::point, compress);
        w.write_meta(meta);
        std::uint64_t seq = 0;
        for (const auto& b : batches) w.write_data(seq++, b.data(), b.size());
        w.finish();
    }
    std::fclose(f);
    std::string s(buf, len);
    std::free(buf);
    return s;
}

struct Decoded {
    std::vector<std::vector<PointRecord>> batches;
    StreamMeta meta;
};

Decoded decode(const std::string& bytes) {
    std::FILE* f = fmemopen(const_cast<char*>(bytes.data()), bytes.size(), "rb");
    if (bytes.empty()) f = std::tmpfile();
    Decoded d;
    try {
        StreamReader r(f, "mem");
        r.read_meta();
        d.meta = r.meta();
        std::vector<char> buf;
        while (true) {
            buf.clear();
            auto n = r.next_data(buf);
            if (!n) break;
            std::vector<PointRecord> b(*n);
            std::memcpy(b.data(), buf.data(), buf.size());
            d.batches.push_back(std::move(b));
        }
    } catch (...) {
        std::fclose(f);
        throw;
    }
    std::fclose(f);
    return d;
}

bool same(const std::vector<PointRecord>& a, const std::vector<PointRecord>& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(PointRecord)) == 0;
}

}  // namespace

TEST_CASE("stream round trip, raw and zstd", "[stream-codec]") {
    const std::vector<std::vector<PointRecord>> batches{some_points(10, 1), some_points(1000, 2), some_points(1, 3)};
    StreamMeta m;
    m.set("iso", 100.5);
    m.set("source", "vol.raw");
    for (bool compress : {false, true}) {
        const Decoded d = decode(encode(batches, compress, m));
        REQUIRE(d.batches.size() == batches.size());
        for (std::size_t i = 0; i < batches.size(); ++i) CHECK(same(d.batches[i], batches[i]));
        CHECK(d.meta.get_double("iso") == 100.5);
        CHECK(d.meta.get("source") == "vol.raw");
    }
}

TEST_CASE("metadata values with line breaks are stored as one line, the same in memory and in the stream", "[stream-codec]") {
    StreamMeta m;
    m.set("source", "a\nb\rc.raw");
    m.set("producer", "meshless generate 'x\ny.raw'");
    CHECK(m.get("source") == "a\\x0ab\rc.raw");  // (a CR stays: the META reader splits on LF only)
    CHECK(m.get("producer") == "meshless generate 'x\\x0ay.raw'");
    const Decoded d = decode(encode({some_points(3, 1)}, false, m));
    CHECK(d.meta.kv == m.kv);
}

TEST_CASE("an empty stream is valid", "[stream-codec]") {
    const Decoded d = decode(encode({}, false));
    CHECK(d.batches.empty());
}

TEST_CASE("garbage, empty, wrong version and wrong record size are refused", "[stream-codec]") {
    CHECK_THROWS_WITH(decode(""), Catch::Contains("empty input"));
    CHECK_THROWS_WITH(decode("hello world, this is not a stream at all"), Catch::Contains("not a meshless point stream"));
    // the first bytes quoted (escaped), and a PLY or VTK file named as such
    CHECK_THROWS_WITH(decode("\x1b[31mred alert and more bytes"), Catch::Contains("(starts \"\\x1b[31mred ale\")"));
    CHECK_THROWS_WITH(decode("ply\nformat binary_little_endian 1.0\n"), Catch::Contains("it is a PLY file"));
    CHECK_THROWS_WITH(decode("<?xml version=\"1.0\"?>\n<VTKFile type=\"PolyData\">"), Catch::Contains("XML (VTK) file"));
    std::string s = encode({some_points(4, 1)}, false);
    std::string v2 = s;
    v2[8] = 2;  // version field
    CHECK_THROWS_WITH(decode(v2), Catch::Contains("version 2 is not supported"));
    std::string big_endian = s;  // a version written big-endian reads as a huge number
    std::swap(big_endian[8], big_endian[11]);
    CHECK_THROWS_WITH(decode(big_endian), Catch::Contains("not supported"));
    std::string rs = s;
    rs[16] = 33;  // record size
    CHECK_THROWS_WITH(decode(rs), Catch::Contains("record size"));
}

TEST_CASE("truncation at every byte is reported, never a short result", "[stream-codec]") {
    const std::string s = encode({some_points(3, 1), some_points(2, 2)}, false);
    for (std::size_t cut = 0; cut < s.size(); ++cut) {
        INFO("cut at " << cut << " of " << s.size());
        CHECK_THROWS_AS(decode(s.substr(0, cut)), FormatError);
    }
    CHECK_NOTHROW(decode(s));
}

TEST_CASE("a flipped bit anywhere in a frame is detected", "[stream-codec]") {
    for (bool compress : {false, true}) {
        const std::string s = encode({some_points(50, 1)}, compress);
        int detected = 0, total = 0;
        for (std::size_t byte = 32; byte < s.size(); byte += 7) {
            std::string t = s;
            t[byte] ^= 0x10;
            ++total;
            try {
                const Decoded d = decode(t);
                // a flip in a skipped field (seq, flags of END) may go unnoticed only if the data is intact
                REQUIRE(d.batches.size() == 1);
                CHECK(same(d.batches[0], some_points(50, 1)));
            } catch (const FormatError&) {
                ++detected;
            }
        }
        CHECK(detected > total / 2);
    }
}

TEST_CASE("unknown frame types are skipped", "[stream-codec]") {
    std::string s = encode({some_points(2, 1)}, false);
    // insert a frame of type 99 with a 4-byte payload right after the stream header
    unsigned char h[32] = {};
    h[0] = 99;
    h[24] = 4;
    const unsigned char payload[4] = {1, 2, 3, 4};
    // crc32 of {1,2,3,4} computed by the codec's own rule: build via a writer is not possible, so
    // compute with zlib's polynomial here
    std::uint32_t crc = 0xffffffffu;
    for (unsigned char b : payload) {
        crc ^= b;
        for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0xedb88320u & (0u - (crc & 1u)));
    }
    crc ^= 0xffffffffu;
    for (int i = 0; i < 4; ++i) h[28 + i] = static_cast<unsigned char>(crc >> (8 * i));
    s.insert(32, std::string(reinterpret_cast<char*>(h), 32) + std::string(reinterpret_cast<const char*>(payload), 4));
    const Decoded d = decode(s);
    REQUIRE(d.batches.size() == 1);
    CHECK(same(d.batches[0], some_points(2, 1)));
}

TEST_CASE("metadata text round trip", "[stream-codec]") {
    StreamMeta m;
    m.set("producer", "meshless generate a b\nc");
    m.set("iso", -0.125);
    const StreamMeta back = StreamMeta::parse(m.serialize(), "x");
    CHECK(back.get("producer") == "meshless generate a b\\x0ac");  // line breaks escaped by set()
    CHECK(back.get_double("iso") == -0.125);
    CHECK_THROWS_AS(StreamMeta::parse("no equals sign\n", "x"), FormatError);
    StreamMeta bad;
    bad.set("iso", "abc");
    CHECK_THROWS_AS(bad.get_double("iso"), FormatError);
}

TEST_CASE("a point stream without blocks keeps the version-1 header bytes, seeds and blocks get theirs", "[stream-codec]") {
    // golden header of a plain point stream: magic, version 1, kind 1, record size 32, flags 0, reserved 0
    const std::string s = encode({some_points(2, 1)}, false);
    const unsigned char golden[32] = {0x89, 'M', 'L', 'S', '\r', '\n', 0x1a, '\n', 1, 0, 0, 0, 1, 0, 0, 0,
                                      32,   0,   0,   0,   0,    0,    0,    0,   0, 0, 0, 0, 0, 0, 0, 0};
    REQUIRE(s.size() > 32);
    CHECK(std::memcmp(s.data(), golden, 32) == 0);
    CHECK(record_size(RecordKind::point) == 32);
    CHECK(record_size(RecordKind::point, kStreamFlagBlocks) == 36);
    CHECK(record_size(RecordKind::sample) == 88);
    CHECK(record_size(RecordKind::seed) == 40);

    char* buf = nullptr;
    std::size_t len = 0;
    std::FILE* f = open_memstream(&buf, &len);
    {
        StreamWriter w(f, "mem", RecordKind::point, false, kStreamFlagBlocks);
        w.write_meta({});
        std::vector<char> packed;
        const auto p = some_points(3, 4);
        const std::uint32_t blocks[3] = {7, 0, 4000000000u};
        interleave_point_blocks(p.data(), blocks, 3, packed);
        w.write_data(0, packed.data(), 3);
        w.finish();
    }
    std::fclose(f);
    const std::string b(buf, len);
    std::free(buf);
    CHECK(static_cast<unsigned char>(b[16]) == 36);
    CHECK(static_cast<unsigned char>(b[20]) == 1);  // flags bit 0
    std::FILE* in = fmemopen(const_cast<char*>(b.data()), b.size(), "rb");
    {
        StreamReader r(in, "mem");
        CHECK(r.has_blocks());
        r.read_meta();
        std::vector<char> raw;
        REQUIRE(r.next_data(raw) == 3u);
        std::vector<PointRecord> p;
        std::vector<std::uint32_t> blk;
        deinterleave_point_blocks(raw.data(), 3, p, blk);
        CHECK(same(p, some_points(3, 4)));
        CHECK(blk == std::vector<std::uint32_t>{7, 0, 4000000000u});
        CHECK(!r.next_data(raw));
    }
    std::fclose(in);

    CHECK_THROWS_AS(StreamWriter(stdout, "x", RecordKind::sample, false, kStreamFlagBlocks), InvalidArgument);
}

TEST_CASE("unknown header flags, block flags on samples or seeds, and seed record sizes are refused", "[stream-codec]") {
    const std::string s = encode({some_points(2, 1)}, false);
    std::string flags = s;
    flags[20] = 2;  // an unknown flag
    CHECK_THROWS_WITH(decode(flags), Catch::Contains("unknown stream header flags"));
    std::string blocks_wrong_size = s;
    blocks_wrong_size[20] = 1;  // blocks flagged, record size still 32
    CHECK_THROWS_WITH(decode(blocks_wrong_size), Catch::Contains("record size 32 does not match"));
    std::string seed = s;
    seed[12] = 5;  // seeds are 40 bytes
    CHECK_THROWS_WITH(decode(seed), Catch::Contains("expected 40"));
    seed[16] = 40;
    seed[20] = 1;
    CHECK_THROWS_WITH(decode(seed), Catch::Contains("only points carry them"));
    std::string mesh = s;
    mesh[12] = 3;  // mesh batches never go on a pipe
    CHECK_THROWS_WITH(decode(mesh), Catch::Contains("unknown record kind 3"));
}

TEST_CASE("a stream written to a pipe has the bytes of one written to memory", "[stream-codec]") {
    // frames larger than the pipe's buffer (widened to 1 MiB), small ones and the header before them
    const std::vector<std::vector<PointRecord>> batches = {some_points(3, 1), some_points(70000, 2), some_points(1, 3),
                                                           {}, some_points(40000, 4)};
    StreamMeta meta;
    meta.set("iso", 0.5);
    for (const bool compress : {false, true}) {
        const std::string expected = encode(batches, compress, meta);
        int fds[2];
        REQUIRE(::pipe(fds) == 0);
        std::string got;
        std::thread reader([&] {
            char buf[65536];
            for (ssize_t n; (n = ::read(fds[0], buf, sizeof buf)) > 0;) got.append(buf, static_cast<std::size_t>(n));
            ::close(fds[0]);
        });
        std::FILE* f = ::fdopen(fds[1], "wb");
        REQUIRE(f != nullptr);
        {
            StreamWriter w(f, "pipe", RecordKind::point, compress);
            w.write_meta(meta);
            std::uint64_t seq = 0;
            for (const auto& b : batches) w.write_data(seq++, b.data(), b.size());
            w.finish();
        }
        std::fclose(f);
        reader.join();
        CHECK(got == expected);
        const Decoded d = decode(got);
        REQUIRE(d.batches.size() == 4);
        CHECK(same(d.batches[1], batches[1]));
    }
}

TEST_CASE("a pipe whose reader has gone is a BrokenPipe, not an I/O error", "[stream-codec]") {
    const auto old = std::signal(SIGPIPE, SIG_IGN);
    int fds[2];
    REQUIRE(::pipe(fds) == 0);
    ::close(fds[0]);
    std::FILE* f = ::fdopen(fds[1], "wb");
    REQUIRE(f != nullptr);
    const auto pts = some_points(1000, 1);
    CHECK_THROWS_AS(
        [&] {
            StreamWriter w(f, "pipe", RecordKind::point);
            w.write_data(0, pts.data(), pts.size());
            w.finish();
        }(),
        BrokenPipe);
    std::fclose(f);
    std::signal(SIGPIPE, old);
}

TEST_CASE("frames larger than the proven-read threshold decode, raw and zstd, and a zstd claim beyond its payload is refused", "[stream-codec]") {
    // 300,000 points = 9.6 MB per frame: read (or decompressed) through the staged, data-proven path
    const std::vector<PointRecord> big = some_points(300000, 3);
    for (bool compress : {false, true}) {
        INFO("zstd " << compress);
        const Decoded d = decode(encode({big, some_points(5, 4)}, compress));
        REQUIRE(d.batches.size() == 2);
        CHECK(same(d.batches[0], big));
        CHECK(same(d.batches[1], some_points(5, 4)));
    }
    // the zstd frame claims more records than its payload decompresses to (the CRC covers the
    // payload only, so it still matches): refused as corrupt, whichever path the claim takes
    for (std::uint64_t extra : {std::uint64_t{1}, std::uint64_t{1} << 24}) {
        std::string s = encode({big}, true);
        std::size_t at = 32;
        while (s[at] != 2) at += 32 + (static_cast<unsigned char>(s[at + 24]) | static_cast<unsigned char>(s[at + 25]) << 8 |
                                       static_cast<unsigned char>(s[at + 26]) << 16 | std::size_t{static_cast<unsigned char>(s[at + 27])} << 24);
        std::uint64_t count = 0;
        std::memcpy(&count, s.data() + at + 16, 8);
        REQUIRE(count == big.size());
        count += extra;
        std::memcpy(s.data() + at + 16, &count, 8);
        INFO("claimed " << count << " records");
        CHECK_THROWS_WITH(decode(s), Catch::Contains("corrupt compressed frame"));
    }
}

namespace {
/// A stream of several isovalues: metadata listing them, then one segment frame and one DATA frame
/// of `batches[k]` per segment; `segment_no` gives the number each segment frame carries.
std::string encode_segments(const std::vector<std::vector<PointRecord>>& batches, const std::vector<std::uint64_t>& segment_no) {
    char* buf = nullptr;
    std::size_t len = 0;
    std::FILE* f = open_memstream(&buf, &len);
    {
        StreamWriter w(f, "mem", RecordKind::point, false);
        StreamMeta m;
        m.set("isovalues", "1.5,2.5");
        w.write_meta(m);
        for (std::size_t k = 0; k < batches.size(); ++k) {
            StreamMeta keys;
            keys.set("iso", 1.5 + static_cast<double>(k));
            w.write_segment(segment_no[k], keys);
            w.write_data(k, batches[k].data(), batches[k].size());
        }
        w.finish();
    }
    std::fclose(f);
    std::string s(buf, len);
    std::free(buf);
    return s;
}
}  // namespace

TEST_CASE("segments: read through as one, or one at a time with their keys, out of order refused", "[stream-codec]") {
    const auto a = some_points(5, 1), b = some_points(7, 2);
    const std::string bytes = encode_segments({a, b}, {0, 1});
    {  // a reader that does not stop at segments reads every record; the segment keys stay out of meta()
        const Decoded d = decode(bytes);
        REQUIRE(d.batches.size() == 2);
        CHECK(d.batches[0].size() == 5);
        CHECK(d.batches[1].size() == 7);
        CHECK(d.meta.get("isovalues") == "1.5,2.5");
        CHECK(!d.meta.get("iso"));
        CHECK(!d.meta.get("segment"));
    }
    {  // stopping at segments: each segment's keys, then its records only
        std::FILE* f = fmemopen(const_cast<char*>(bytes.data()), bytes.size(), "rb");
        StreamReader r(f, "mem");
        r.stop_at_segments();
        r.read_meta();
        std::vector<char> buf;
        CHECK(!r.next_data(buf));  // the first segment frame comes before any record
        for (int k = 0; k < 2; ++k) {
            const auto seg = r.next_segment();
            REQUIRE(seg);
            CHECK(seg->get("segment") == std::to_string(k));
            CHECK(seg->get_double("iso") == 1.5 + k);
            buf.clear();
            REQUIRE(r.next_data(buf));
            CHECK(buf.size() == (k == 0 ? 5u : 7u) * sizeof(PointRecord));
            CHECK(!r.next_data(buf));
        }
        CHECK(!r.next_segment());
        CHECK(r.segments() == 2);
        CHECK(r.total() == 12);
        std::fclose(f);
    }
    // a segment number out of order (a spliced stream) is refused by both kinds of reader
    const std::string spliced = encode_segments({a, b}, {0, 2});
    CHECK_THROWS_WITH(decode(spliced), Catch::Contains("segment frame '2' where segment 1 was due (after 5 records)"));
    const std::string late = encode_segments({a}, {1});
    CHECK_THROWS_WITH(decode(late), Catch::Contains("segment frame '1' where segment 0 was due"));
}

TEST_CASE("segments: records before the first segment frame are refused by a reader that stops at them", "[stream-codec]") {
    char* buf = nullptr;
    std::size_t len = 0;
    std::FILE* f = open_memstream(&buf, &len);
    const auto a = some_points(3, 1);
    {
        StreamWriter w(f, "mem", RecordKind::point, false);
        w.write_meta({});
        w.write_data(0, a.data(), a.size());
        StreamMeta keys;
        keys.set("iso", 1.0);
        w.write_segment(0, keys);
        w.write_data(1, a.data(), a.size());
        w.finish();
    }
    std::fclose(f);
    const std::string bytes(buf, len);
    std::free(buf);
    std::FILE* in = fmemopen(const_cast<char*>(bytes.data()), bytes.size(), "rb");
    StreamReader r(in, "mem");
    r.stop_at_segments();
    r.read_meta();
    CHECK_THROWS_WITH(r.next_segment(), Catch::Contains("mem: records before the first segment frame"));
    std::fclose(in);
}
