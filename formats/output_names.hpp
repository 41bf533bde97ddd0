// Outputs are chosen by extension: the one place that checks an output's name against what is
// written to it (a point set, a mesh, a PNG, a store, a binary stream between stages) and refuses
// binary bytes on a terminal. "-" (standard output), a device or a FIFO pass any extension
// (formats/atomic_file.hpp is_streaming_output). Every check throws InvalidArgument (exit code 1
// in cli/) with one line naming the option, the path and what the output is; nothing else throws.
#pragma once
#include <optional>
#include <string>

#include "formats/geometry_format.hpp"

namespace meshless {

/// InvalidArgument "refusing to write WHAT to a terminal" when `path` is "-" and standard output is
/// a terminal (binary outputs: streams, PLY, VTP, PNG, NRRD, stores).
void refuse_binary_to_terminal(const std::string& path, const std::string& what);

/// Returns `path` when it ends in `ext` (".ply", ".png", ...; case-insensitive) or is a stream;
/// otherwise InvalidArgument naming `option`, the path and `what` it writes (a file named out.vtp must
/// not receive PLY bytes). Every output but .csv is binary: "-" on a terminal is refused
/// (refuse_binary_to_terminal). to_stdout = false: the output cannot go to standard output (a store,
/// a fit, a tree: regular files only), so the message does not offer '-'.
const std::string& require_output_extension(const std::string& path, const char* ext, const char* option, const char* what,
                                            bool to_stdout = true);

/// InvalidArgument unless formats/point_set_writer.hpp takes this -o name (.ply, .csv, .vtp or "-");
/// `what` says what the output is ("a level of detail").
void require_point_set_output(const std::string& path, const char* what);

/// The geometry format of the -o `path` of `what` (e.g. "an oriented point set"): its extension (.ply
/// or .vtp, any case) or `format` (--format ply|vtp). With `format`, the path must not end in the
/// other format's extension; a stream without it is PLY (what pipes always got). Any other name
/// without `format`, or a `format` other than ply|vtp, is an InvalidArgument; so is "-" when
/// standard output is a terminal.
GeometryFormat geometry_output_format(const std::string& path, const std::optional<std::string>& format, const char* what);

/// InvalidArgument when `path` (a stream output of `what`, e.g. "a sample stream") has the extension
/// of a format the stream is not (out.ply, out.csv, out.png, ...: the stream would not open in the
/// programs that name promises); "-", FIFOs, devices and other names pass. Point streams are
/// conventionally named .mlp.
void check_stream_output_name(const std::string& path, const char* what);

}  // namespace meshless
