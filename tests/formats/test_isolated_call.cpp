// A call in a child process of its own: its output comes back, its exception's text, an abort or a
// crash becomes a result (this process lives on), a child past its deadline is killed.
#include <catch2/catch.hpp>

#include <unistd.h>

#include <csignal>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <vector>

#include "formats/isolated_call.hpp"

using namespace meshless;

TEST_CASE("isolated call: output, exceptions, aborts, crashes and deadlines", "[formats][isolated]") {
    std::vector<std::byte> out(1000, std::byte{0});
    IsolatedResult r = run_isolated(out.size(), out.data(), [](std::byte* b) {
        for (int i = 0; i < 1000; ++i) b[i] = static_cast<std::byte>(i % 251);
    }, 30);
    CHECK(r.outcome == IsolatedResult::Outcome::ok);
    CHECK(out[999] == static_cast<std::byte>(999 % 251));
    out.assign(1000, std::byte{7});
    r = run_isolated(out.size(), out.data(), [](std::byte* b) {
        b[0] = std::byte{1};
        throw std::runtime_error("x.dcm: bad stream");
    }, 30);
    CHECK(r.outcome == IsolatedResult::Outcome::error);
    CHECK(r.message == "x.dcm: bad stream");
    CHECK(out[0] == std::byte{7});  // nothing copied from a failed child
    r = run_isolated(8, out.data(), [](std::byte*) { std::abort(); }, 30);
    CHECK(r.outcome == IsolatedResult::Outcome::crashed);
    CHECK(r.signal == SIGABRT);
    r = run_isolated(8, out.data(), [](std::byte*) { ::raise(SIGSEGV); }, 30);
    CHECK(r.outcome == IsolatedResult::Outcome::crashed);
    CHECK(r.signal == SIGSEGV);
    r = run_isolated(8, out.data(), [](std::byte*) { ::sleep(30); }, 1);
    CHECK(r.outcome == IsolatedResult::Outcome::timed_out);
}
