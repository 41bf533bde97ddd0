// Projection of one paradigm-(C) sample onto the isosurface f = iso of its cell's trilinear
// interpolant (dissertation section 3.3): `approx` = one Newton step with the displacement criterion
// (Eq. 3.5, section 3.3.2), `exact` = ray-trilinear intersection by the cubic of Eq. 3.3 (section
// 3.3.1), `none` = the unprojected sample (left image of Fig. 3.4).
//
// The output normal is the unit gradient of the cell's trilinear interpolant at the output position
// (falling back to the sample's gradient where that vanishes), oriented towards increasing values;
// the output value is the interpolant there. Rejected samples return false and are counted.
// Pure and reentrant.
#pragma once
#include <cstdint>
#include <string_view>

#include "kernels/records.hpp"

namespace meshless {

enum class Projection { none, approx, exact };

/// "none" | "approx" | "exact"; throws UsageError otherwise.
Projection parse_projection(std::string_view s);
const char* to_string(Projection p);

struct ProjectionStats {
    std::int64_t input = 0;         ///< samples seen
    std::int64_t output = 0;        ///< points emitted
    std::int64_t too_far = 0;       ///< approx: Newton step longer than delta_d (Fig. 3.3)
    std::int64_t flat = 0;          ///< approx: zero gradient
    std::int64_t missed = 0;        ///< exact: no ray hit the isosurface inside the cell
    ProjectionStats& operator+=(const ProjectionStats& o) {
        input += o.input; output += o.output; too_far += o.too_far; flat += o.flat; missed += o.missed;
        return *this;
    }
};

/// Projects s onto f = iso. Returns false (and counts why) when the sample is discarded.
bool project_sample(const SampleRecord& s, double iso, Projection mode, PointRecord& out,
                    ProjectionStats& stats);

}  // namespace meshless
