// Scattered points as delimited text: CSV, TSV or whitespace-separated columns (dissertation
// chapters 4-5 inputs).
//
// Layouts recognised: a header line of column names ("x,y,z,value"; quotes stripped), or no
// header (columns by index), or a first line holding only the point count (gravi.txt: the count,
// then 5 columns x y z anomaly error; the count is checked), or tagged lines ("p x y z", as in
// .pts point clouds: only 'p'/'v' lines are points, positions only). Lines starting with '#',
// '%' or '//' and blank lines are skipped. Delimiter: ',' if the first data line has one, else
// ';', else tabs/whitespace.
// Columns: options.columns ("x,y,z,value" by name or 0-based index; three entries = positions
// only), else x/y/z by name (case-insensitive) or columns 0,1,2; the value is options.value_name
// / value_index, else the first header column that is not x/y/z, else column 3 when present.
// Throws FormatError naming the path and line (empty file, malformed header, missing columns,
// a row with the wrong field count, a bad number, a count line that disagrees), IoError.
// Thread-safety: reentrant.
#pragma once
#include <string>
#include <vector>

#include "formats/point_set_options.hpp"

namespace meshless {

PointSet read_points_text(const std::string& path, const PointSetOptions& options,
                          std::vector<std::string>* notes = nullptr);

}  // namespace meshless
