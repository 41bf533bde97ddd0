// The isosurface options the Python module's functions share (python/README.md), checked as the
// commands check them: the projection (`--projection`), the isovalue, the Newton settings of the
// meshless projections (`--tolerance`, `--max-iterations`, `--max-travel`, stream/field_project_stage.hpp)
// and the seeds per triangle edge (`--samples`, kernels/barycentric_lattice.hpp). Each throws
// ValueError (pybind11::value_error) naming the option for a value out of range.
#pragma once
#include <string>

#include "kernels/project_sample.hpp"
#include "stream/field_project_stage.hpp"

namespace meshless::python {

/// "approx", "exact" or "none".
Projection projection_of(const std::string& s);
/// iso itself when finite.
double finite_iso(double iso);
/// tolerance in (0, 1] of the cell diagonal, 1..1000 iterations, max_travel >= 0 cell diagonals (0: no limit).
FieldProjectParams newton_params(double tolerance, int max_iterations, double max_travel);
/// 1..kMaxLatticeN seeds per triangle edge.
int lattice(int samples);

}  // namespace meshless::python
