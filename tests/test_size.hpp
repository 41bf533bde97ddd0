// Input sizes of the tests whose inputs are big (tens of thousands of points for numerics at scale):
// the sanitizer tier (MESHLESS_SANITIZED: AddressSanitizer at -O1 runs the field construction
// 30-60x slower) runs them at a reduced size that still meets each test's premises; so does any
// build with MESHLESS_TEST_SMALL=1 in the environment, which is how the reduced sizes are checked
// without an instrumented build (docs/development.md, "The sanitizer tier").
#pragma once
#include <cstddef>
#include <cstdlib>
#include <cstring>

namespace meshless::test {

/// True in the sanitizer tier, or with MESHLESS_TEST_SMALL=1.
inline bool reduced_test_sizes() {
#ifdef MESHLESS_SANITIZED
    return true;
#else
    const char* e = std::getenv("MESHLESS_TEST_SMALL");
    return e && std::strcmp(e, "1") == 0;
#endif
}

/// `full`, or `reduced` under reduced_test_sizes().
template <class T>
T test_size(T full, T reduced) {
    return reduced_test_sizes() ? reduced : full;
}

}  // namespace meshless::test
