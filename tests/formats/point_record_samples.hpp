// Deterministic oriented point records for the VTP writer and reader tests: positions on a curve,
// unit normals in the xy plane, radii and values that vary with the index.
#pragma once
#include <cmath>
#include <cstdint>

#include "kernels/records.hpp"

namespace meshless::test {

inline PointRecord sample_point_record(std::uint64_t i) {
    const double t = static_cast<double>(i);
    PointRecord p{};
    p.pos[0] = static_cast<float>(std::sin(t * 0.37) * 10);
    p.pos[1] = static_cast<float>(std::cos(t * 0.11) * 5);
    p.pos[2] = static_cast<float>(t * 1e-3);
    p.normal[0] = static_cast<float>(std::cos(t));
    p.normal[1] = static_cast<float>(std::sin(t));
    p.normal[2] = 0;
    p.radius = static_cast<float>(0.5 + (i % 7) * 0.01);
    p.value = static_cast<float>(i % 101) - 50.25f;
    return p;
}

}  // namespace meshless::test
