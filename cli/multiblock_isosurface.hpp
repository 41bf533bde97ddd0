// The multiblock/AMR isosurface (dissertation chapter 4, sections 4.3-4.6) on the command line:
//   meshless isosurface BLOCKS... --iso V -o out.ply [--png out.png] [--field KIND] [--samples N] ...
//   meshless generate BLOCKS... --iso V [--samples N]            (a seed stream)
//   meshless project --field KIND DATA... [< seeds]              (seed stream -> points with blocks)
// Option parsing over the recipes of stream/block_isosurface.hpp (block cells -> marching-cubes seeds
// on the barycentric lattice -> Newton onto one continuous meshless field built from every block's
// valid nodes) and stream/block_isosurface_job.hpp (-> PLY with a `block` property and/or PNG, the
// --stats block). The piped stages give the same bytes as the in-process command for any --threads
// (same batches, same field from the same data).
// cmd_isosurface / cmd_generate / cmd_project hand their arguments here when formats/input_kind.hpp names_blocks() /
// project_seeds_invocation() say so. Throws UsageError for bad options, what the readers and
// stages throw otherwise (cli/app.cpp maps them to exit codes).
#pragma once
#include <cstdio>
#include <initializer_list>
#include <memory>
#include <optional>
#include <string>

#include "cli/args.hpp"
#include "formats/atomic_file.hpp"
#include "formats/input_kind.hpp"
#include "formats/point_stream.hpp"
#include "kernels/field_newton_projection.hpp"
#include "stream/block_isosurface.hpp"
#include "stream/field_project_stage.hpp"
#include "stream/projection_meta.hpp"

namespace meshless::cli {


// Shared with the scattered-data isosurface (cli/scattered_isosurface.hpp), which seeds and
// projects the same way:
/// --samples N (the barycentric lattice parameter, default kDefaultLatticeN) and its value.
void add_samples_option(Args& a, int default_n = kDefaultLatticeN);
int lattice_n(const Args& a, int default_n = kDefaultLatticeN);
/// --tolerance --max-iterations --max-travel (Newton onto the field, relative to each seed's cell;
/// --max-travel's default: kDefaultMaxTravel, stream/projection_meta.hpp).
void add_newton_options(Args& a);
FieldProjectParams newton_params(const Args& a);
/// -o FILE (an oriented point set: .ply, .vtp, '-') and --png FILE of an isosurface command,
/// checked (one at least; not the same file); returns --png. Throws UsageError.
std::optional<std::string> point_outputs_png(const Args& a);

/// The positional arguments of argv[first..argc) under the option declarations of `parsers`
/// (an option that takes a value in any of them consumes the next argument).
std::vector<std::string> scan_positionals(int argc, char** argv, int first, std::initializer_list<const Args*> parsers);

int isosurface_blocks(int argc, char** argv);
int generate_blocks(int argc, char** argv);
/// `meshless project` given --field: a seed stream projected onto the field of DATA...
int project_seeds(int argc, char** argv);
/// True when argv (from index 2) has a --field option (project then reads seeds).
bool project_seeds_invocation(int argc, char** argv);

}  // namespace meshless::cli
