// The warning of a job whose isovalue cannot give a surface: the data has no finite value, or the
// isovalue lies outside the data's value range (the outputs are then empty but valid). One line
// "meshless: warning: SOURCE: ..." with SOURCE passed through formats/terminal_safe.hpp. Nothing
// is thrown.
#pragma once
#include <array>
#include <cstdio>
#include <string>

namespace meshless {

/// Warns on `out` when iso lies outside [lo, hi] = range (NaN lo: no finite samples); true when it warned.
/// one_of_several: iso is one of a run's several isovalues (the line says its surface is empty, not the outputs).
bool warn_if_iso_outside(double iso, const std::array<double, 2>& range, const std::string& source, std::FILE* out = stderr,
                         bool one_of_several = false);

}  // namespace meshless
