// cli/args.hpp: the command-line value parsers (parse_memory_size, the --memory syntax, moved here
// from ooc/: the library takes bytes).
#include <catch2/catch.hpp>

#include "cli/args.hpp"
#include "cli/errors.hpp"

using namespace meshless::cli;

TEST_CASE("parse_memory_size", "[cli]") {
    CHECK(parse_memory_size("256M") == 256ull << 20);
    CHECK(parse_memory_size("1G") == 1ull << 30);
    CHECK(parse_memory_size("512k") == 512ull << 10);
    CHECK(parse_memory_size("512K") == 512ull << 10);
    CHECK(parse_memory_size("1048576") == 1048576ull);
    CHECK(parse_memory_size("64MiB") == 64ull << 20);
    CHECK(parse_memory_size("2GB") == 2ull << 30);
    CHECK(parse_memory_size("100B") == 100ull);
    CHECK(parse_memory_size("1T") == 1ull << 40);
    for (const char* bad : {"", "M", "abc", "12X", "-5", "0", "1.5G", "99999999999999999999", "16777216T", "5 M B"})
        CHECK_THROWS_AS(parse_memory_size(bad), UsageError);
    CHECK_THROWS_WITH(parse_memory_size("12X"), Catch::Contains("--memory") && Catch::Contains("'12X'"));
}

namespace {
bool parse_tokens(Args& a, std::vector<std::string> tokens) {
    std::vector<char*> argv;
    for (auto& t : tokens) argv.push_back(t.data());
    return a.parse(static_cast<int>(argv.size()), argv.data(), 1);
}
}  // namespace

TEST_CASE("a single-valued option given twice is a usage error, a repeatable one is not", "[cli]") {
    {
        Args a("isosurface", "VOLUME", "");
        a.option("iso", "", "V", "isovalue").option("at", "", "X,Y,Z", "position").repeatable().flag("stats", "");
        CHECK_THROWS_WITH(parse_tokens(a, {"isosurface", "--iso", "1", "v.nrrd", "--iso=2"}),
                          Catch::Contains("--iso given twice") && Catch::Contains("'1' and '2'"));
    }
    {
        Args a("probe", "POINTS", "");
        a.option("iso", "", "V", "isovalue").option("at", "", "X,Y,Z", "position").repeatable().flag("stats", "");
        REQUIRE(parse_tokens(a, {"probe", "--at", "1,2,3", "--at", "4,5,6", "--iso", "7", "--stats", "--stats"}));
        CHECK(a.get_all("at") == std::vector<std::string>{"1,2,3", "4,5,6"});
        CHECK(a.get("iso") == std::optional<std::string>("7"));
    }
    Args b("x", "", "");
    b.flag("stats", "");
    CHECK_THROWS_AS(b.repeatable(), std::logic_error);
}
