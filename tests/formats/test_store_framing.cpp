// formats/store_framing: the preamble every store checks first, one must-fail case per defect class
// (too short for a magic, wrong magic, too short for a version, another version, too short for the
// header and footer), each a FormatError naming the file; a well-formed preamble passes; the footer
// round-trips its fields; formats/spool_file appends and reads back at offsets and leaves no file.
#include <catch2/catch.hpp>

#include <cstring>
#include <filesystem>
#include <string>

#include <unistd.h>

#include "formats/spool_file.hpp"
#include "formats/store_framing.hpp"
#include "kernels/errors.hpp"

using namespace meshless;

namespace {
constexpr char kMagic[8] = {'\x89', 'T', 'S', 'T', '\r', '\n', '\x1a', '\n'};
const StoreFraming kFraming{"test store", std::string_view(kMagic, 8), 3, 64, "; remake it"};

std::string preamble(std::uint32_t version, std::size_t total) {
    std::string s(kMagic, 8);
    s.append(reinterpret_cast<const char*>(&version), 4);
    s.resize(total, '\0');
    return s;
}

std::string failure(const std::string& bytes) {
    const StoreReadAt read = [&](void* dst, std::size_t n, std::uint64_t off) {
        REQUIRE(off + n <= bytes.size());  // the checks never read past what they proved is there
        std::memcpy(dst, bytes.data() + off, n);
    };
    try {
        check_store_preamble(read, bytes.size(), "f.tst", kFraming);
    } catch (const FormatError& e) {
        return e.what();
    }
    return "";
}
}  // namespace

TEST_CASE("store preamble: one FormatError per defect class, naming the file", "[formats][store-framing]") {
    CHECK(failure("") == "f.tst: not a meshless test store (file of 0 bytes)");
    CHECK(failure(std::string(7, 'x')) == "f.tst: not a meshless test store (file of 7 bytes)");
    CHECK(failure(std::string(100, 'x')) == "f.tst: not a meshless test store (bad magic)");
    CHECK(failure(preamble(3, 100).substr(0, 10)) == "f.tst: truncated test store (10 bytes)");
    CHECK(failure(preamble(4, 100)) == "f.tst: unsupported test store version 4 (this build reads version 3; remake it)");
    CHECK(failure(preamble(3, 95)) == "f.tst: truncated test store (95 bytes; header and footer need 96)");
    CHECK(failure(preamble(3, 96)).empty());
}

TEST_CASE("store footer: offset, entries, CRC, version and end magic at their bytes", "[formats][store-framing]") {
    const auto f = encode_store_footer(0x0102030405060708ull, 42, 0xdeadbeefu, 7, std::string_view("ENDMAGIC", 8));
    CHECK(get_le<std::uint64_t>(f.data()) == 0x0102030405060708ull);
    CHECK(get_le<std::uint64_t>(f.data() + 8) == 42);
    CHECK(get_le<std::uint32_t>(f.data() + 16) == 0xdeadbeefu);
    CHECK(get_le<std::uint32_t>(f.data() + 20) == 7);
    CHECK(std::memcmp(f.data() + 24, "ENDMAGIC", 8) == 0);
}

TEST_CASE("spool file: appends return offsets, reads give the bytes back, nothing left after", "[formats][store-framing]") {
    const auto dir = std::filesystem::temp_directory_path() / ("meshless-spool-" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    const std::string out = (dir / "out.bin").string();
    {
        SpoolFile spool(out);
        CHECK(spool.append("hello", 5) == 0);
        CHECK(spool.append(" world", 6) == 5);
        CHECK(spool.size() == 11);
        char back[6] = {};
        spool.read(5, 6, back);
        CHECK(std::string(back, 6) == " world");
        CHECK(std::distance(std::filesystem::directory_iterator(dir), std::filesystem::directory_iterator{}) == 1);
        CHECK_THROWS_AS(spool.read(8, 6, back), IoError);  // past the end
    }
    CHECK(std::filesystem::is_empty(dir));
    std::filesystem::remove_all(dir);
}
