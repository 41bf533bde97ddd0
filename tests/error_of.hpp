// Test helper: the message of the exception a call throws, for CHECK_THAT(..., Contains(...)).
// error_of<E...>(f) runs f and returns what() of the first exception of one of the types E (default
// FormatError); any other exception propagates (the test fails), and no exception gives
// "(nothing thrown)", which no expected message contains.
#pragma once
#include <string>

#include "kernels/errors.hpp"

namespace meshless::test {

template <class... E>
struct ErrorOf;

template <>
struct ErrorOf<> {
    template <class F>
    static std::string run(F& f) {
        f();
        return "(nothing thrown)";
    }
};

template <class E, class... Rest>
struct ErrorOf<E, Rest...> {
    template <class F>
    static std::string run(F& f) {
        try {
            return ErrorOf<Rest...>::run(f);
        } catch (const E& e) {
            return e.what();
        }
    }
};

template <class... E, class F>
std::string error_of(F&& f) {
    if constexpr (sizeof...(E) == 0) return ErrorOf<FormatError>::run(f);
    else return ErrorOf<E...>::run(f);
}

}  // namespace meshless::test
