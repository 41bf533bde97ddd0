// vtk-js HttpDataSetReader image layout: a directory (often named *.vti) holding index.json
// with vtkClass "vtkImageData", extent[6], spacing[3], origin[3] and pointData.arrays[].data
// {dataType (Int8Array..Float64Array), numberOfComponents, size, ref {basepath, id, encode}};
// the array bytes are in BASEPATH/ID.gz (gzip) or BASEPATH/ID (raw, or gzip by magic).
// The array whose data.name is `array` is read when given, else the one registered with
// "setScalars", else the first; one component only. The plan lists every array with 'data'
// (PayloadPlan::arrays).
// `path` may be the directory or the index.json itself.
// Throws IoError (cannot open index or array file), FormatError (bad JSON, not vtkImageData, no
// array called `array` (formats/payload.hpp choose_volume_array),
// unsupported dataType/components, size mismatch, corrupt gzip). Thread-safety: reentrant.
// Dissertation: chapter 3 input volumes.
#pragma once
#include <string>

#include "formats/payload.hpp"

namespace meshless {

/// index.json for a directory path, the path itself otherwise.
std::string vtkjs_index_path(const std::string& path);
/// `refs`: where the array file (BASEPATH/ID) may lie (formats/reference_policy.hpp): checked before
/// the file is looked at; ReferenceRefused outside it.
PayloadPlan plan_vtkjs_image(const std::string& path, const ReferencePolicy& refs = {},
                             const std::string& array = "");
VolumeInfo probe_vtkjs_image(const std::string& path, const ReferencePolicy& refs = {},
                             const std::string& array = "");
Volume read_vtkjs_image(const std::string& path, const ReferencePolicy& refs = {},
                        const std::string& array = "");

}  // namespace meshless
