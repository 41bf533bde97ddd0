// CLI helper of paradigm (A) (dissertation section 3.5, Table 3.1) shared by `meshless extract`
// (cli/cmd_extract.cpp) and the .mls input of `meshless isosurface`.
#pragma once
#include <string>

#include "cli/common.hpp"
#include "ooc/sample_store.hpp"

namespace meshless::cli {

/// The META of paradigm (C) over the store's .mlb (volume_meta) plus paradigm=A: both paradigms
/// give the same PLY comments.
StreamMeta sample_store_meta(const SampleStore& store, double iso, const std::string& producer);

}  // namespace meshless::cli
