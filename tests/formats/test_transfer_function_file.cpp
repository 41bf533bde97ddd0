// Transfer-function files (formats/transfer_function_file.hpp): a good file with comments, commas
// and a step; must-fail files per defect class, each naming FILE:LINE.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>

#include "formats/transfer_function_file.hpp"
#include "kernels/errors.hpp"
#include "tests/error_of.hpp"
#include "tests/test_paths.hpp"

using namespace meshless;
using Catch::Matchers::Contains;

namespace {
std::string write(const test::TempDir& d, const std::string& name, const std::string& text) {
    const auto p = (d / name).string();
    std::ofstream(p, std::ios::binary) << text;
    return p;
}
}  // namespace

TEST_CASE("transfer-function file: rows, comments, commas and steps are read", "[render]") {
    test::TempDir d("tf");
    const auto p = write(d, "ok.tf",
                         "# value r g b a\n"
                         "0    0 0 0 0\n"
                         "\n"
                         "50,  1, 0.5, 0, 0.25   # comma separated\r\n"
                         "50\t0\t0\t1\t1\n"
                         "100 1 1 1 1e-1");
    const TransferFunction tf = read_transfer_function_file(p);
    REQUIRE(tf.points().size() == 4);
    CHECK(tf.at(25)[0] == Approx(0.5));
    CHECK(tf.at(50)[2] == 1);
    CHECK(tf.at(100)[3] == Approx(0.1));
}

TEST_CASE("transfer-function file: each defect is refused with FILE:LINE", "[render]") {
    test::TempDir d("tf");
    struct Case {
        const char* text;
        const char* line;
        const char* what;
    };
    const Case cases[] = {
        {"0 0 0 0 0\n10 1 1 1 1\n5 1 1 1 1\n", ":3:", "sorted"},
        {"0 0 0 0 0\n1 0 0 0 1.5\n", ":2:", "outside [0, 1]"},
        {"0 -0.1 0 0 0\n", ":1:", "outside [0, 1]"},
        {"# c\n0 0 0 0\n", ":2:", "expected 5 numbers"},
        {"0 0 0 0 0 0\n", ":1:", "expected 5 numbers"},
        {"0 0 zero 0 0\n", ":1:", "not a finite number"},
        {"nan 0 0 0 0\n", ":1:", "not a finite number"},
        {"1e999 0 0 0 0\n", ":1:", "not a finite number"},
        {"0 0 0 0 0x\n", ":1:", "not a finite number"},
        {"0 0 0 0 \x01\xff\n", ":1:", "\\x01\\xff"},
    };
    for (const Case& c : cases) {
        const auto p = write(d, "bad.tf", c.text);
        const std::string msg = test::error_of([&] { read_transfer_function_file(p); });
        INFO(c.text);
        CHECK_THAT(msg, Contains(p + c.line) && Contains(c.what));
    }
    const auto empty = write(d, "empty.tf", "# nothing\n\n");
    CHECK_THAT(test::error_of([&] { read_transfer_function_file(empty); }), Contains("no 'value r g b a' rows"));
    const std::string long_line(5000, '1');
    const auto longf = write(d, "long.tf", long_line + "\n");
    CHECK_THAT(test::error_of([&] { read_transfer_function_file(longf); }), Contains(":1:"));
    CHECK_THROWS_AS(read_transfer_function_file((d / "absent.tf").string()), IoError);
    CHECK_THROWS_AS(read_transfer_function_file(d.path.string()), IoError);
}
