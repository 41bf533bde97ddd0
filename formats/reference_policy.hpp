// Reference confinement: where the files a header names may lie. A detached header (NRRD `data
// file`, MetaImage `ElementDataFile`, Voreen `ObjectFileName`, a vtk-js index's `basepath`/`id`, a
// NIfTI pair's .img) makes a reader open other files; a reader given a confined policy refuses any
// such file, and the input itself, whose resolved path leaves the policy's root folder.
//
// Resolution: std::filesystem::weakly_canonical of the absolute path, so `..`, `.` and every
// symbolic link of the existing part of the path are resolved; the root is resolved the same way.
// The comparison is by path components ("/a/bc" is not inside "/a/b"). An unconfined policy (the
// default, an empty root) lets references go wherever the format allows, as VTK and teem do.
// Who confines: `meshless batch` (its archive folder, cli/cmd_batch.cpp); the other commands read
// what the user names, following references.
// Throws ReferenceRefused (below), a FormatError: one line naming the header, the
// reference as written (escaped), its resolved path and the root. Thread-safety: reentrant.
// Dissertation: none (input plumbing).
#pragma once
#include <string>
#include <vector>

#include "kernels/errors.hpp"

namespace meshless {

/// A file named by a header (or the input itself) resolves outside the folder the reader was
/// confined to: the input is refused, nothing of that file is read. A FormatError, so it maps like
/// one (exit 2); `meshless batch` reports the input as refused and goes on.
struct ReferenceRefused : FormatError {
    using FormatError::FormatError;
};

struct ReferencePolicy {
    /// Empty: unconfined. Otherwise the folder every file read through the input must resolve into.
    std::string root;
    bool confined() const { return !root.empty(); }
};

/// `file`'s resolved path: weakly_canonical of its absolute path (`..` and symbolic links resolved
/// as far as the path exists), or its lexically normal absolute path when that fails.
std::string resolved_path(const std::string& file);

/// True when `file` resolves to `root` (resolved) or to a path below it, compared component-wise.
bool resolves_inside(const std::string& file, const std::string& root);

/// Nothing when unconfined or when `file` resolves inside the root; else ReferenceRefused
/// "HEADER: names FILE (resolved: PATH), outside the archive folder ROOT; refused". `header` is the
/// file that names `file` (for the input itself, header == file: "INPUT: resolves to PATH ...").
void check_reference(const ReferencePolicy& policy, const std::string& header, const std::string& file);

/// check_reference for each of `files`.
void check_references(const ReferencePolicy& policy, const std::string& header, const std::vector<std::string>& files);

}  // namespace meshless
