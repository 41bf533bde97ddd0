// The folder that outputs go to (`meshless batch -o DIR`, `meshless demo DIR`), made when missing.
//
// Throws IoError "DIR: cannot create output folder: WHY" (a file of that name exists, or the
// system's reason) when `dir` is not a folder afterwards; an existing folder is no error.
// Reentrant.
#pragma once
#include <string>

namespace meshless {

/// Creates the folder `dir` (and its parents) for outputs (see above).
void make_output_folder(const std::string& dir);

}  // namespace meshless
