// formats/gzip.hpp: whole-buffer inflate (libdeflate) and the streamed reader (zlib) give the
// same bytes for zlib streams, gzip members and concatenated members; short, long, truncated and
// corrupt data, and a claim beyond deflate's 1032:1, fail with a message naming the file.
#include <catch2/catch.hpp>

#include <functional>
#include <numeric>
#include <string>

#include "formats/gzip.hpp"
#include "kernels/errors.hpp"
#include "tests/formats/format_test_util.hpp"
#include "tests/test_paths.hpp"

using namespace meshless;
using namespace meshless::test;

namespace {

std::vector<std::byte> pattern(std::size_t n) {
    std::vector<std::byte> v(n);
    for (std::size_t i = 0; i < n; ++i) v[i] = static_cast<std::byte>((i * 2654435761u) >> 13);
    return v;
}

std::string message_of(const std::function<void()>& f) {
    try {
        f();
    } catch (const FormatError& e) {
        return e.what();
    }
    return "(no FormatError)";
}

}  // namespace

TEST_CASE("gzip: inflate_into and inflate_file agree with the streamed reader", "[formats][gzip]") {
    TempDir d("gzip");
    const auto plain = pattern(300000);
    for (const bool gz : {false, true}) {
        INFO((gz ? "gzip" : "zlib"));
        const auto z = deflate_bytes(plain, gz);
        std::vector<std::byte> out(plain.size());
        inflate_into(z.data(), z.size(), out.data(), out.size(), "mem");
        CHECK(out == plain);

        const std::string f = (d / (gz ? "a.gz" : "a.z")).string();
        write_file(f, "HEAD", z);
        const SampleBytes all = inflate_file(f, 4, 0, plain.size());
        CHECK(std::equal(all.begin(), all.end(), plain.begin(), plain.end()));
        const SampleBytes tail = inflate_file(f, 4, 1000, plain.size() - 1000);  // skip: the bytes after it
        CHECK(std::equal(tail.begin(), tail.end(), plain.begin() + 1000, plain.end()));
        InflateReader r(f, 4);
        std::vector<std::byte> streamed(plain.size());
        r.read_exact(streamed.data(), streamed.size(), "data");
        CHECK(streamed == plain);
    }
}

TEST_CASE("gzip: concatenated members and trailing padding", "[formats][gzip]") {
    TempDir d("gzip-members");
    const auto plain = pattern(5000);
    const std::vector<std::byte> a(plain.begin(), plain.begin() + 2000), b(plain.begin() + 2000, plain.end());
    auto z = deflate_bytes(a, true);
    const auto zb = deflate_bytes(b, true);
    z.insert(z.end(), zb.begin(), zb.end());
    z.insert(z.end(), 16, std::byte{0});  // padding after the last member is ignored
    const std::string f = (d / "m.gz").string();
    write_file(f, "", z);
    const SampleBytes out = inflate_file(f, 0, 0, plain.size());
    CHECK(std::equal(out.begin(), out.end(), plain.begin(), plain.end()));
}

TEST_CASE("gzip: short, long, truncated, corrupt and bomb payloads fail naming the file", "[formats][gzip]") {
    TempDir d("gzip-bad");
    const auto plain = pattern(4096);
    const auto z = deflate_bytes(plain, true);
    const std::string f = (d / "p.gz").string();
    write_file(f, "", z);
    // the stream holds 4096 bytes
    CHECK_THAT(message_of([&] { (void)inflate_file(f, 0, 0, 5000); }),
               Catch::StartsWith(f) && Catch::Contains("compressed data ends after 4096 decompressed bytes, expected 5000"));
    CHECK_THAT(message_of([&] { (void)inflate_file(f, 0, 0, 4000); }),
               Catch::StartsWith(f) && Catch::Contains("decompresses to more than 4000 bytes"));
    std::vector<std::byte> out(4096);
    CHECK_THAT(message_of([&] { inflate_into(z.data(), z.size() / 2, out.data(), out.size(), "half.gz"); }),
               Catch::StartsWith("half.gz") && Catch::Contains("corrupt compressed data"));
    auto bad = z;
    bad[bad.size() - 6] ^= std::byte{0xff};  // the CRC-32 no longer matches
    CHECK_THAT(message_of([&] { inflate_into(bad.data(), bad.size(), out.data(), out.size(), "crc.gz"); }),
               Catch::StartsWith("crc.gz") && Catch::Contains("corrupt compressed data"));
    CHECK_THAT(message_of([&] { inflate_into(z.data(), 0, out.data(), out.size(), "empty.gz"); }),
               Catch::Contains("ends after 0 decompressed bytes"));
    // a claim beyond 1032:1 of the compressed bytes present is refused before anything is allocated
    CHECK_THAT(message_of([&] { (void)inflate_file(f, 0, 0, std::uint64_t(1) << 40); }),
               Catch::StartsWith(f) && Catch::Contains("more than the " + std::to_string(z.size()) + " compressed bytes"));
}
