// The multiblock/AMR isosurface (dissertation chapter 4, sections 4.3-4.6) on the command line:
//   meshless isosurface BLOCKS... --iso V -o out.ply [--png out.png] [--field KIND] [--samples N] ...
//   meshless generate BLOCKS... --iso V [--samples N]            (a seed stream)
//   meshless project --field KIND DATA... [< seeds]              (seed stream -> points with blocks)
// as one graph: block cells -> marching-cubes seeds on the barycentric lattice -> Newton onto one
// continuous meshless field built from every block's valid nodes -> PLY (with a `block` property)
// and/or PNG. The piped stages give the same bytes as the in-process command for any --threads
// (same batches, same field from the same data).
// cmd_isosurface / cmd_generate / cmd_project hand their arguments here when blocks_invocation() /
// project_seeds_invocation() say so. Throws UsageError for bad options, what the readers and
// stages throw otherwise (cli/app.cpp maps them to exit codes).
#pragma once
#include <initializer_list>

#include "cli/args.hpp"

namespace meshless::cli {

/// The default lattice parameter n of --samples (n(n+1)/2 seeds per triangle); see the .cpp for
/// the measurement behind it.
inline constexpr int kDefaultLatticeN = 2;

/// The positional arguments of argv[first..argc) under the option declarations of `parsers`
/// (an option that takes a value in any of them consumes the next argument).
std::vector<std::string> scan_positionals(int argc, char** argv, int first, std::initializer_list<const Args*> parsers);

/// True when the positionals name blocks: several inputs, or one that looks like a multiblock file
/// (formats/multiblock_reader.hpp looks_like_multiblock).
bool blocks_invocation(const std::vector<std::string>& positionals);

int isosurface_blocks(int argc, char** argv);
int generate_blocks(int argc, char** argv);
/// `meshless project` given --field: a seed stream projected onto the field of DATA...
int project_seeds(int argc, char** argv);
/// True when argv (from index 2) has a --field option (project then reads seeds).
bool project_seeds_invocation(int argc, char** argv);

}  // namespace meshless::cli
