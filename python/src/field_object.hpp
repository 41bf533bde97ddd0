// meshless.Field of the Python module: a meshless field (kernels/field.hpp) fitted to NumPy points
// (stream/field_evaluation.hpp fit_field) or loaded from a .mlf (formats/field_file.hpp), with
// what `save` needs to write the same file `meshless fit` writes. point_set_of turns (n, 3) points
// and (n,) values into the PointSet the fields are built from, dropping rows with a NaN/Inf
// coordinate or value as the file readers do (counted in dropped_nonfinite).
// Throws ValueError (pybind11::value_error) for arrays of the wrong shape.
#pragma once
#include <memory>
#include <optional>

#include "arrays.hpp"
#include "formats/field_file.hpp"
#include "kernels/field.hpp"
#include "kernels/field_params.hpp"
#include "kernels/point_set.hpp"

namespace meshless::python {

struct FieldObject {
    std::unique_ptr<Field> field;
    FieldParams params;
    FittedData data;
    FieldBuildStats stats;
};

/// The PointSet of `points` (n, 3) and `values` (n,), non-finite rows dropped.
PointSet point_set_of(const py::array& points, const py::array& values);

}  // namespace meshless::python
