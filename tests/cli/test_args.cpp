// cli/args.hpp: the command-line value parsers (parse_memory_size, the --memory syntax, moved here
// from ooc/: the library takes bytes).
#include <catch2/catch.hpp>

#include <memory>
#include <stdexcept>

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

namespace {
/// The option set of a rendering command, small: values that start with '-' are common here.
void declare_camera(Args& a) {
    a.option("output", "o", "FILE", "output", "out.png")
        .option("up", "", "AXIS", "up axis", "y")
        .option("view", "", "NAME", "named view")
        .option("range", "", "LO,HI", "value range")
        .option("iso", "", "V", "isovalue")
        .option("at", "", "X,Y,Z", "position")
        .repeatable()
        .flag("ortho", "orthographic");
}
}  // namespace

TEST_CASE("Args: --name value, --name=value, short aliases, flags and positionals", "[cli]") {
    Args a("splat", "[INPUT|-]", "");
    declare_camera(a);
    a.positionals(0, 2);
    REQUIRE(parse_tokens(a, {"splat", "-", "-o", "x.png", "--up=z", "--ortho", "--iso", "2.5", "in.ply"}));
    CHECK(a.get("output") == std::optional<std::string>("x.png"));
    CHECK(a.get("up") == std::optional<std::string>("z"));
    CHECK(a.get_double("iso") == std::optional<double>(2.5));
    CHECK(a.has("ortho"));
    CHECK(!a.has("view"));
    CHECK(!a.get("view"));
    CHECK(a.get_or("view", "iso") == "iso");
    CHECK(a.positional() == std::vector<std::string>{"-", "in.ply"});
    CHECK(a.declared("view"));
    CHECK(a.declared("help"));
    CHECK(!a.declared("bogus"));
    CHECK(!a.has("bogus"));
    CHECK(a.command_line() == "splat - -o x.png --up=z --ortho --iso 2.5 in.ply");
}

TEST_CASE("Args: an option's value may start with '-'", "[cli]") {
    Args a("splat", "", "");
    declare_camera(a);
    a.positionals(0, 3);
    REQUIRE(parse_tokens(a, {"splat", "--up", "-z", "--range", "-5,5", "--iso", "-0.5", "--view", "-x", "--at", "-1,-2,-3",
                             "--at=-4,5,6", "-o", "-", "-7", "--", "--ortho", "-y"}));
    CHECK(a.get("up") == std::optional<std::string>("-z"));
    CHECK(a.get("range") == std::optional<std::string>("-5,5"));
    CHECK(a.get_double("iso") == std::optional<double>(-0.5));
    CHECK(a.get("view") == std::optional<std::string>("-x"));
    CHECK(a.get_all("at") == std::vector<std::string>{"-1,-2,-3", "-4,5,6"});
    CHECK(a.get_triple("at").has_value());  // the last one
    CHECK(a.get("output") == std::optional<std::string>("-"));
    // a negative number is a positional; after "--" everything is
    CHECK(a.positional() == std::vector<std::string>{"-7", "--ortho", "-y"});
    CHECK(!a.has("ortho"));
    // an empty value is a value
    Args b("splat", "", "");
    declare_camera(b);
    REQUIRE(parse_tokens(b, {"splat", "--view", "", "--up", "--x"}));
    CHECK(b.get("view") == std::optional<std::string>(""));
    CHECK(b.get("up") == std::optional<std::string>("--x"));  // the next argument, unless it is one of the options
    CHECK_THROWS_WITH(parse_tokens(b, {"splat", "--up", "--ortho"}), Catch::Contains("'--ortho' is an option"));
    // bytes CLI11 gives meaning elsewhere ("[a,b]" lists, "{}", quotes) are plain values and positionals here
    Args c("splat", "", "");
    declare_camera(c);
    c.positionals(0, 2);
    REQUIRE(parse_tokens(c, {"splat", "[a,b]", "--view", "{}", "--up=[x]", "--range", "\"1,2\"", "--at", "[1,2,3]", "'q'"}));
    CHECK(c.positional() == std::vector<std::string>{"[a,b]", "'q'"});
    CHECK(c.get("view") == std::optional<std::string>("{}"));
    CHECK(c.get("up") == std::optional<std::string>("[x]"));
    CHECK(c.get("range") == std::optional<std::string>("\"1,2\""));
    CHECK(c.get_all("at") == std::vector<std::string>{"[1,2,3]"});
}

TEST_CASE("Args: usage errors are one line naming the option", "[cli]") {
    auto error_of = [](std::vector<std::string> tokens, std::size_t max_positionals = 1) {
        Args a("splat", "", "");
        declare_camera(a);
        a.positionals(0, max_positionals);
        try {
            parse_tokens(a, std::move(tokens));
        } catch (const UsageError& e) {
            return std::string(e.what());
        }
        return std::string("(no error)");
    };
    CHECK(error_of({"splat", "--bogus", "1"}) == "unknown option '--bogus' (see meshless splat --help)");
    CHECK(error_of({"splat", "--bogus=1"}) == "unknown option '--bogus' (see meshless splat --help)");
    CHECK(error_of({"splat", "-q"}) == "unknown option '-q' (see meshless splat --help)");
    CHECK(error_of({"splat", "--iso"}) == "option --iso needs a value (V)");
    CHECK(error_of({"splat", "x", "-o"}) == "option --output needs a value (FILE)");
    CHECK(error_of({"splat", "--up", "x", "--up", "-y"}) ==
          "option --up given twice ('x' and '-y'); it takes one value (see meshless splat --help)");
    CHECK(error_of({"splat", "-o", "a.png", "--output=b.png"}) ==
          "option --output given twice ('a.png' and 'b.png'); it takes one value (see meshless splat --help)");
    CHECK(error_of({"splat", "--ortho=1"}) == "option --ortho takes no value");
    CHECK(error_of({"splat", "a", "b"}) == "unexpected argument 'b' (see meshless splat --help)");
    CHECK(error_of({"splat", "a", "b", "c"}, 2) == "unexpected argument 'c' (see meshless splat --help)");
    CHECK(error_of({"splat", "--ortho", "--ortho", "a"}) == "(no error)");  // a flag twice is the flag
    // a value left out before the next option (the newcomer trial's "--iso -o a.ply"), in any spelling
    CHECK(error_of({"splat", "--iso", "-o", "a.png"}) == "option --iso needs a value; '-o' is an option (see meshless splat --help)");
    CHECK(error_of({"splat", "--iso", "--output", "a.png"}) ==
          "option --iso needs a value; '--output' is an option (see meshless splat --help)");
    CHECK(error_of({"splat", "--iso", "--ortho"}) == "option --iso needs a value; '--ortho' is an option (see meshless splat --help)");
    CHECK(error_of({"splat", "--iso", "-5", "-o", "a.png"}) == "(no error)");  // a value may start with '-'
    CHECK(error_of({"splat", "--iso", "--x"}) == "(no error)");  // not an option: a value (refused later if not a number)
    for (const auto& msg : {error_of({"splat", "--iso", "1", "--iso", "2"}), error_of({"splat", "--bogus"})})
        CHECK(msg.find('\n') == std::string::npos);
    // malformed numbers, read by the getters
    Args a("splat", "", "");
    declare_camera(a);
    REQUIRE(parse_tokens(a, {"splat", "--iso", "1e", "--at", "1,2"}));
    CHECK_THROWS_WITH(a.get_double("iso"), "--iso: expected a number, got '1e'");
    CHECK_THROWS_WITH(a.get_triple("at"), Catch::Contains("--at: expected three comma-separated numbers"));
    CHECK_THROWS_WITH(a.require("view"), Catch::Contains("missing required option --view"));
}

TEST_CASE("Args: --help and takes_value", "[cli]") {
    Args a("splat", "[INPUT|-] -o img.png", "Renders points.");
    declare_camera(a);
    a.epilog("example: meshless splat in.ply -o x.png\n");
    CHECK(a.takes_value("--up"));
    CHECK(a.takes_value("-o"));
    CHECK(!a.takes_value("--ortho"));
    CHECK(!a.takes_value("--help"));
    CHECK(!a.takes_value("--bogus"));
    CHECK(!a.takes_value("-"));
    CHECK(!a.takes_value("--up=z"));
    const std::string h = a.help_text();
    CHECK(h.rfind("usage: meshless splat [INPUT|-] -o img.png\n\nRenders points.\n", 0) == 0);
    CHECK_THAT(h, Catch::Contains("  -o, --output FILE         output (default out.png)\n"));
    CHECK_THAT(h, Catch::Contains("  --up AXIS                 up axis (default y)\n"));
    CHECK_THAT(h, Catch::Contains("  --ortho                   orthographic\n"));
    CHECK_THAT(h, Catch::Contains("\nexample: meshless splat in.ply -o x.png\n\nexit codes: 0 success"));
    // --help wins over the errors on its line; parse() says so by returning false
    Args b("splat", "", "");
    declare_camera(b);
    CHECK(!parse_tokens(b, {"splat", "--help", "--iso", "1", "--iso", "2", "--bogus"}));
}

TEST_CASE("Args: a long option description is wrapped under its column", "[cli]") {
    Args a("x", "", "");
    a.option("long", "", "N", std::string(50, 'a') + " " + std::string(30, 'b') + "\n                   " + "c");
    CHECK_THAT(a.help_text(), Catch::Contains("  --long N                  " + std::string(50, 'a') + "\n" +
                                              std::string(28, ' ') + std::string(30, 'b') + " c\n"));
}

TEST_CASE("a validated option is checked at parse whether or not the command reads it", "[cli]") {
    auto args = [] {
        auto a = std::make_unique<Args>("mc", "VOLUME", "");
        a->option("memory", "", "BYTES", "budget").validate([](const std::string& v) { (void)parse_memory_size(v); });
        a->option("at", "", "X", "repeatable").repeatable().validate([](const std::string& v) {
            if (v == "bad") throw UsageError("--at: bad");
        });
        return a;
    };
    CHECK(parse_tokens(*args(), {"mc", "v.raw", "--memory", "1G"}));
    CHECK(parse_tokens(*args(), {"mc", "v.raw"}));  // absent: nothing to check
    CHECK_THROWS_WITH(parse_tokens(*args(), {"mc", "v.raw", "--memory", "lots"}), Catch::Contains("'lots'"));
    CHECK(parse_tokens(*args(), {"mc", "--at", "a", "--at", "b"}));
    CHECK_THROWS_WITH(parse_tokens(*args(), {"mc", "--at", "a", "--at", "bad"}), Catch::Contains("--at: bad"));
    // --help wins over a bad value
    CHECK_FALSE(parse_tokens(*args(), {"mc", "--memory", "lots", "--help"}));
    Args flagged("mc", "", "");
    flagged.flag("stats", "");
    CHECK_THROWS_AS(flagged.validate([](const std::string&) {}), std::logic_error);
}

TEST_CASE("Args: a deprecated alias works as the new name, hidden from --help, and not both at once", "[cli]") {
    {
        Args a("convert", "VOLUME", "");
        a.option("zstd-level", "", "N", "zstd level", "1").deprecated_alias("level").flag("value-range", "scan").deprecated_alias("range");
        REQUIRE(parse_tokens(a, {"convert", "v.nrrd", "--level", "3", "--range"}));
        CHECK(a.get("zstd-level") == std::optional<std::string>("3"));
        CHECK(a.has("value-range"));
        CHECK(a.takes_value("--level"));
        CHECK(a.help_text().find("--zstd-level") != std::string::npos);
        CHECK(a.help_text().find("--level") == std::string::npos);
    }
    {
        Args a("convert", "VOLUME", "");
        a.option("zstd-level", "", "N", "zstd level", "1").deprecated_alias("level");
        REQUIRE(parse_tokens(a, {"convert", "v.nrrd", "--zstd-level=4"}));
        CHECK(a.get("zstd-level") == std::optional<std::string>("4"));
    }
    Args b("convert", "VOLUME", "");
    b.option("zstd-level", "", "N", "zstd level", "1").deprecated_alias("level");
    CHECK_THROWS_WITH(parse_tokens(b, {"convert", "--zstd-level", "2", "--level", "3"}),
                      Catch::Contains("--zstd-level given twice") && Catch::Contains("--level"));
}
