// formats/binary_file.hpp: FileRangeReader reads the ranges asked for, refuses directories and
// FIFOs at open (a FIFO without a writer must not block), names the file and the range when the
// range passes the end, and reports a file that shrank after opening as a short read.
#include <catch2/catch.hpp>

#include <sys/stat.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "formats/binary_file.hpp"
#include "kernels/errors.hpp"
#include "tests/test_paths.hpp"

using namespace meshless;
using namespace meshless::test;

namespace {

void write_bytes(const std::filesystem::path& p, std::size_t n) {
    std::ofstream f(p, std::ios::binary);
    for (std::size_t i = 0; i < n; ++i) f.put(static_cast<char>((i * 131u + 7u) & 255u));
}

}  // namespace

TEST_CASE("FileRangeReader: ranges of one open file", "[formats][binary_file]") {
    TempDir dir("range_reader");
    const auto p = dir.path / "data.bin";
    write_bytes(p, 10000);
    const FileRangeReader r(p.string());
    CHECK(r.size() == 10000);
    const std::vector<std::byte> whole = read_file_bytes(p.string());
    REQUIRE(whole.size() == 10000);
    for (std::uint64_t off : {0ull, 1ull, 4095ull, 9000ull}) {
        std::vector<std::byte> got(1000 - (off == 9000 ? 0 : 1));
        r.read_into(off, got.size(), got.data());
        CHECK(std::equal(got.begin(), got.end(), whole.begin() + static_cast<std::ptrdiff_t>(off)));
    }
    std::byte none{};
    r.read_into(10000, 0, &none);  // an empty range at the end is fine
    CHECK_THROWS_WITH(r.read_into(9990, 11, &none),
                      Catch::Contains("data.bin: truncated: need 11 bytes at offset 9990, file has 10000"));
    CHECK_THROWS_AS(r.read_into(20000, 1, &none), FormatError);
}

TEST_CASE("FileRangeReader: a file that shrinks after opening is a short read", "[formats][binary_file]") {
    TempDir dir("range_reader_shrink");
    const auto p = dir.path / "shrinks.bin";
    write_bytes(p, 4096);
    const FileRangeReader r(p.string());
    std::filesystem::resize_file(p, 100);
    std::vector<std::byte> buf(4096);
    CHECK_THROWS_WITH(r.read_into(0, 4096, buf.data()),
                      Catch::Contains("shrinks.bin: read failed at offset 100: unexpected end of file"));
}

TEST_CASE("FileRangeReader: missing files, directories and FIFOs are refused at open", "[formats][binary_file]") {
    TempDir dir("range_reader_kinds");
    CHECK_THROWS_WITH(FileRangeReader((dir.path / "missing.raw").string()), Catch::Contains("missing.raw: cannot open"));
    CHECK_THROWS_WITH(FileRangeReader(dir.path.string()), Catch::Contains("is a directory, expected a file"));
    const auto fifo = dir.path / "pipe.raw";
    REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
    // no writer: a blocking open would hang here
    CHECK_THROWS_WITH(FileRangeReader(fifo.string()), Catch::Contains("pipe.raw: not a regular file (a FIFO"));
    CHECK_THROWS_AS(read_file_range_into(fifo.string(), 0, 1, nullptr), IoError);
}
