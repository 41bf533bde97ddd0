// File names a user may really have: a line break or an escape sequence in a volume's name. The
// outputs that quote the name (a PLY's comment) stay well-formed and identical across pipes, and
// nothing the commands print (info's description, batch's lines and table, warnings) carries a
// control byte to the terminal.
#include <catch2/catch.hpp>

#include <filesystem>
#include <string>

#include "cli_harness.hpp"

using namespace meshless;
using namespace meshless::test;

namespace {
/// No ESC, CR or LF other than the line ends of `text`'s own lines (each line is "...\n").
bool one_line_each(const std::string& text) {
    for (std::size_t i = 0; i < text.size(); ++i) {
        const auto c = static_cast<unsigned char>(text[i]);
        if (c == 0x1b || c == '\r' || (c < 0x20 && c != '\n' && c != '\t')) return false;
    }
    return true;
}
}  // namespace

TEST_CASE("a volume whose name holds a line break: the PLY quotes it escaped, the same bytes through pipes", "[cli][names]") {
    TempDir d("names-newline");
    const std::string vol = write_uint8_analytic_volume(d, "nl\nx", AnalyticField::torus, 24, 200.0, 0.0);
    // the shell names it by a glob (? matches the line break)
    const std::string glob = (d / "nl?x_24x24x24_uint8.raw").string();
    const auto in = sh("MESHLESS isosurface " + glob + " --iso 100.5 -o " + (d / "in.ply").string(), d);
    REQUIRE(in.code == 0);
    const std::string ply = slurp(d / "in.ply");
    const std::size_t end = ply.find("end_header\n");
    REQUIRE(end != std::string::npos);
    const std::string header = ply.substr(0, end);
    CHECK_THAT(header, Catch::Contains("comment source nl\\x0ax_24x24x24_uint8.raw\n"));
    CHECK(header.find("nl\nx") == std::string::npos);
    // the header still parses: info reads the body through
    const auto info = sh("MESHLESS info " + (d / "in.ply").string(), d);
    CHECK(info.code == 0);
    const auto pipe = sh("MESHLESS generate " + glob + " --iso 100.5 | MESHLESS project | MESHLESS write -o " + (d / "pipe.ply").string(), d);
    REQUIRE(pipe.code == 0);
    CHECK(slurp(d / "pipe.ply") == ply);
    // the warning that quotes the name is one line
    const auto warn = sh("MESHLESS isosurface " + glob + " --iso 1000 -o " + (d / "empty.ply").string(), d);
    CHECK(warn.code == 0);
    CHECK_THAT(warn.err, Catch::Contains("nl\\x0ax_24x24x24_uint8.raw: isovalue 1000 is outside"));
    CHECK(one_line_each(warn.err));
}

TEST_CASE("info and batch print names with escape sequences escaped", "[cli][names]") {
    TempDir d("names-escape");
    const std::string arch = (d / "arch").string();
    std::filesystem::create_directories(d / "arch");
    const std::string made = write_uint8_analytic_volume(d, "esc\x1b[31mx", AnalyticField::torus, 16, 200.0, 0.0);
    std::filesystem::rename(made, d / "arch" / std::filesystem::path(made).filename());
    spit(d / "arch" / "bad\x1b[1m_8x8x8_uint8.raw", "too short");
    const std::string glob_ok = (d / "arch" / "esc?\\[31mx_16x16x16_uint8.raw").string();
    const std::string glob_bad = (d / "arch" / "bad?\\[1m_8x8x8_uint8.raw").string();

    const auto ok = sh("MESHLESS info " + glob_ok, d);
    CHECK(ok.code == 0);
    CHECK_THAT(ok.out, Catch::Contains("esc\\x1b[31mx_16x16x16_uint8.raw: raw volume"));
    CHECK(one_line_each(ok.out));
    const auto bad = sh("MESHLESS info " + glob_bad + " /nonexistent/\x1b[2Jgone.raw", d);
    CHECK(bad.code == 2);
    CHECK_THAT(bad.err, Catch::Contains("bad\\x1b[1m_8x8x8_uint8.raw"));
    CHECK_THAT(bad.err, Catch::Contains("\\x1b[2Jgone.raw"));
    CHECK(one_line_each(bad.err));

    const auto batch = sh("MESHLESS batch " + arch + " -o " + (d / "out").string() + " --iso 100.5 --formats ply", d);
    CHECK(batch.code == 2);  // the short file fails, the other converts
    CHECK_THAT(batch.out, Catch::Contains("esc\\x1b[31mx_16x16x16_uint8"));
    CHECK_THAT(batch.err, Catch::Contains("bad\\x1b[1m_8x8x8_uint8"));
    CHECK(one_line_each(batch.out));
    CHECK(one_line_each(batch.err));
}
