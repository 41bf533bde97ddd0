// cli/errors.hpp: the one mapping from exceptions to exit codes and messages (through a real
// command: test_ooc_pipeline.cpp, a --memory below one brick is the library's InvalidArgument, exit 1),
// and cli/common.hpp's parse_projection (the --projection syntax, moved here from kernels/).
#include <catch2/catch.hpp>

#include <new>
#include <stdexcept>

#include "cli/common.hpp"
#include "cli/errors.hpp"
#include "kernels/errors.hpp"

using namespace meshless;
using namespace meshless::cli;

TEST_CASE("exit codes: usage 1, data and I/O 2, internal 3, broken pipe 0", "[cli]") {
    CHECK(exit_code(UsageError("--iso: expected a number")) == kExitUsage);
    CHECK(exit_code(InvalidArgument("--brick: brick edge must be 2..1024 cells, got 1")) == kExitUsage);
    CHECK(exit_code(FormatError("a.nrrd: bad magic")) == kExitData);
    CHECK(exit_code(IoError("a.nrrd: cannot open")) == kExitData);
    CHECK(exit_code(std::bad_alloc()) == kExitData);
    CHECK(exit_code(BrokenPipe()) == kExitOk);
    CHECK(exit_code(std::runtime_error("oops")) == kExitInternal);
    CHECK(exit_code(std::invalid_argument("a programmer error")) == kExitInternal);
    CHECK(exit_code(std::length_error("too long")) == kExitInternal);

    CHECK(error_message(UsageError("--iso: expected a number")) == "--iso: expected a number");
    CHECK(error_message(InvalidArgument("x: bad")) == "x: bad");
    CHECK(error_message(FormatError("a.nrrd: bad magic")) == "a.nrrd: bad magic");
    CHECK(error_message(std::bad_alloc()) == "out of memory");
    CHECK(error_message(std::runtime_error("oops")) == "internal error: oops");
}

TEST_CASE("parse_projection: the --projection names", "[cli]") {
    CHECK(parse_projection("none") == Projection::none);
    CHECK(parse_projection("approx") == Projection::approx);
    CHECK(parse_projection("exact") == Projection::exact);
    for (const Projection p : {Projection::none, Projection::approx, Projection::exact})
        CHECK(parse_projection(to_string(p)) == p);
    CHECK_THROWS_AS(parse_projection("Exact"), UsageError);
    CHECK_THROWS_WITH(parse_projection(""), Catch::Contains("--projection"));
}
