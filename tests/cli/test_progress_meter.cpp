// cli/progress_meter.hpp: the progress line's text (percent, rate, ETA), its delay and rate limit,
// thread-safe counting, clearing; against a fake clock and a temporary file.
#include <catch2/catch.hpp>

#include <cstdio>
#include <string>
#include <thread>
#include <vector>

#include "cli/progress_meter.hpp"

using namespace meshless::cli;

namespace {
std::string contents(std::FILE* f) {
    std::fflush(f);
    std::rewind(f);
    std::string s;
    for (int c; (c = std::fgetc(f)) != EOF;) s.push_back(static_cast<char>(c));
    return s;
}
}  // namespace

TEST_CASE("progress line: percent, rate and ETA", "[cli][progress]") {
    double now = 0;
    std::FILE* f = std::tmpfile();
    REQUIRE(f);
    ProgressMeter m("meshless slice", "pixels", 1000, true, 1.0, f, [&] { return now; });
    CHECK(m.line(250, 2.0) == "meshless slice:  25% 125 pixels/s, ETA 0:06");
    CHECK(m.line(0, 0) == "meshless slice:   0%");
    CHECK(m.line(1000, 4000.0) == "meshless slice: 100% 0.25 pixels/s, ETA 0:00");
    ProgressMeter big("x", "voxels", 4e9, true, 1.0, f, [&] { return now; });
    CHECK(big.line(1e9, 500.0) == "x:  25% 2M voxels/s, ETA 25:00");
    CHECK(big.line(1e9, 3600.0) == "x:  25% 278k voxels/s, ETA 3:00:00");
    CHECK(big.line(999.7e3, 1.0) == "x:   0% 1M voxels/s, ETA 1:06:40");  // not "1e+03k"
    CHECK(big.line(999.4e3, 1.0).find(" 999k voxels/s") != std::string::npos);
    std::fclose(f);
}

TEST_CASE("progress line: nothing in the first second, at most 4 lines a second, cleared at the end", "[cli][progress]") {
    double now = 0;
    std::FILE* f = std::tmpfile();
    REQUIRE(f);
    {
        ProgressMeter m("p", "items", 100, true, 1.0, f, [&] { return now; });
        m.add(10);
        now = 0.9;
        m.add(10);
        CHECK(contents(f).empty());
        now = 1.0;
        m.add(10);  // 30 of 100 after 1 s
        std::fseek(f, 0, SEEK_END);
        now = 1.1;
        m.add(10);  // too soon after the last line
        now = 1.3;
        m.set_fraction(0.5);
        m.done();
        m.done();
    }
    const std::string s = contents(f);
    CHECK(s == "\r\033[Kp:  30% 30 items/s, ETA 0:02\r\033[Kp:  50% 38.5 items/s, ETA 0:01\r\033[K");
    std::fclose(f);
}

TEST_CASE("progress: disabled draws nothing, counts from many threads add up", "[cli][progress]") {
    std::FILE* f = std::tmpfile();
    REQUIRE(f);
    double now = 5;
    {
        ProgressMeter off("p", "items", 100, false, 0.0, f, [&] { return now; });
        off.add(50);
    }
    CHECK(contents(f).empty());
    ProgressMeter m("p", "items", 4000, true, 1e9, f, [&] { return now; });  // never draws
    std::vector<std::thread> ts;
    for (int t = 0; t < 4; ++t)
        ts.emplace_back([&] {
            for (int i = 0; i < 1000; ++i) m.add(1);
        });
    for (auto& t : ts) t.join();
    CHECK(m.done_units() == 4000);
    CHECK(m.line(4000, 1) == "p: 100% 4k items/s, ETA 0:00");
    std::fclose(f);
}
