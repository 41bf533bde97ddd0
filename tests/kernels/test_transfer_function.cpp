// Transfer functions (kernels/transfer_function.hpp): piecewise-linear lookup, clamping, steps,
// the exact maximum opacity over an interval against brute force, validation, presets.
#include <catch2/catch.hpp>

#include <cmath>
#include <random>

#include "kernels/errors.hpp"
#include "kernels/transfer_function.hpp"

using namespace meshless;

TEST_CASE("transfer function interpolates linearly, clamps at the ends and takes the right side of a step", "[render]") {
    const TransferFunction tf({{0, 0, 0, 0, 0}, {10, 1, 0.5, 0, 0.4}, {10, 0, 0, 1, 1}, {20, 0, 1, 1, 0.5}});
    CHECK(tf.at(-5)[3] == 0);
    CHECK(tf.at(5)[0] == Approx(0.5));
    CHECK(tf.at(5)[3] == Approx(0.2));
    CHECK(tf.at(9.999)[3] == Approx(0.4).margin(1e-3));
    CHECK(tf.at(10)[2] == 1);  // the step: the later point from 10 on
    CHECK(tf.at(15)[1] == Approx(0.5));
    CHECK(tf.at(99)[3] == 0.5);
    const auto nan = tf.at(std::nan(""));
    CHECK(nan[3] == 0);
}

TEST_CASE("maximum opacity over an interval equals brute force and is 0 only where nothing shows", "[render]") {
    const TransferFunction tf({{0, 0, 0, 0, 0}, {3, 0, 0, 0, 0}, {4, 1, 1, 1, 0.7}, {5, 1, 1, 1, 0.1}, {8, 1, 1, 1, 0}});
    std::mt19937 rng(1);
    std::uniform_real_distribution<double> u(-2, 10);
    for (int i = 0; i < 2000; ++i) {
        double a = u(rng), b = u(rng);
        if (a > b) std::swap(a, b);
        double brute = 0;
        for (int k = 0; k <= 4000; ++k) brute = std::max(brute, tf.at(a + (b - a) * k / 4000.0)[3]);
        CHECK(tf.max_opacity(a, b) >= brute - 1e-12);
        CHECK(tf.max_opacity(a, b) <= brute + 2e-3 * 0.7);  // brute force samples may miss the peak a little
    }
    CHECK(tf.max_opacity(0.5, 2.9) == 0);
    CHECK(tf.max_opacity(8, 100) == 0);
    CHECK(tf.max_opacity(2.9, 3.1) > 0);
    CHECK(tf.max_opacity(1, 0) == 0);              // empty interval (no finite sample)
    CHECK(tf.max_opacity(std::nan(""), 1) == 1);   // unknown: never skipped
}

TEST_CASE("transfer function refuses unsorted, out-of-range and non-finite points", "[render]") {
    CHECK_THROWS_AS(TransferFunction({}), InvalidArgument);
    CHECK_THROWS_AS(TransferFunction({{1, 0, 0, 0, 0}, {0, 0, 0, 0, 0}}), InvalidArgument);
    CHECK_THROWS_AS(TransferFunction({{0, 1.5, 0, 0, 0}}), InvalidArgument);
    CHECK_THROWS_AS(TransferFunction({{0, 0, 0, 0, -0.1}}), InvalidArgument);
    CHECK_THROWS_AS(TransferFunction({{std::nan(""), 0, 0, 0, 0}}), InvalidArgument);
    CHECK_THROWS_AS(TransferFunction({{INFINITY, 0, 0, 0, 0}}), InvalidArgument);
    CHECK_NOTHROW(TransferFunction({{0, 0, 0, 0, 0}, {0, 1, 1, 1, 1}}));  // a step
}

TEST_CASE("transfer function presets span the value range they are given", "[render]") {
    for (auto name : transfer_function_preset_names()) {
        const TransferFunction tf = transfer_function_preset(name, 100, 300);
        CHECK(tf.lo() == 100);
        CHECK(tf.hi() == 300);
        CHECK(tf.at(300)[3] > 0);
        CHECK(is_transfer_function_preset(name));
    }
    CHECK(transfer_function_preset("ct-bone", 0, 255).max_opacity(0, 0.5 * 255) == 0);  // air and soft tissue skipped
    CHECK_THROWS_AS(transfer_function_preset("nope", 0, 1), InvalidArgument);
    CHECK_THROWS_AS(transfer_function_preset("grey", 1, 1), InvalidArgument);
    CHECK_FALSE(is_transfer_function_preset("tf.txt"));
}
