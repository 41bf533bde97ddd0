#include "kernels/project_sample.hpp"

#include "kernels/errors.hpp"
#include "kernels/exact_projection.hpp"
#include "kernels/newton_projection.hpp"
#include "kernels/trilinear.hpp"

namespace meshless {

Projection parse_projection(std::string_view s) {
    if (s == "none") return Projection::none;
    if (s == "approx") return Projection::approx;
    if (s == "exact") return Projection::exact;
    throw UsageError("--projection: expected none, approx or exact, got '" + std::string(s) + "'");
}

const char* to_string(Projection p) {
    switch (p) {
        case Projection::none: return "none";
        case Projection::approx: return "approx";
        case Projection::exact: return "exact";
    }
    return "?";
}

}  // namespace meshless
