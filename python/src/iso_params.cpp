#include "iso_params.hpp"

#include <pybind11/pybind11.h>

#include <cmath>
#include <limits>

#include "kernels/barycentric_lattice.hpp"

namespace meshless::python {

namespace py = pybind11;

Projection projection_of(const std::string& s) {
    if (s == "approx") return Projection::approx;
    if (s == "exact") return Projection::exact;
    if (s == "none") return Projection::none;
    throw py::value_error("projection: expected 'approx', 'exact' or 'none', got '" + s + "'");
}

double finite_iso(double iso) {
    if (!std::isfinite(iso)) throw py::value_error("iso: expected a finite number");
    return iso;
}

FieldProjectParams newton_params(double tolerance, int max_iterations, double max_travel) {
    if (!(tolerance > 0) || tolerance > 1) throw py::value_error("tolerance: expected a fraction of the cell diagonal in (0, 1]");
    if (max_iterations < 1 || max_iterations > 1000) throw py::value_error("max_iterations: expected 1..1000");
    if (!(max_travel >= 0)) throw py::value_error("max_travel: expected a number of cell diagonals >= 0 (0: no limit)");
    FieldProjectParams p;
    p.seed_tolerance = tolerance;
    p.newton.max_iterations = max_iterations;
    p.seed_max_travel = max_travel == 0 ? std::numeric_limits<double>::infinity() : max_travel;
    return p;
}

int lattice(int samples) {
    if (samples < 1 || samples > kMaxLatticeN) throw py::value_error("samples: expected 1.." + std::to_string(kMaxLatticeN));
    return samples;
}

}  // namespace meshless::python
