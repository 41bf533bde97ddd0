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
