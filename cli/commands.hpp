// Entry points of the meshless subcommands; each parses its own arguments (argv[1] is the
// subcommand name), returns an exit code, and lets exceptions reach cli_main (cli/app.cpp), which
// maps them to exit codes.
#pragma once

namespace meshless::cli {

int cmd_demo(int argc, char** argv);
int cmd_isosurface(int argc, char** argv);
int cmd_generate(int argc, char** argv);
int cmd_project(int argc, char** argv);
int cmd_write(int argc, char** argv);
int cmd_extract(int argc, char** argv);
int cmd_splat(int argc, char** argv);
int cmd_render(int argc, char** argv);
int cmd_mc(int argc, char** argv);
int cmd_info(int argc, char** argv);
int cmd_fit(int argc, char** argv);
int cmd_probe(int argc, char** argv);
int cmd_slice(int argc, char** argv);
int cmd_resample(int argc, char** argv);
int cmd_batch(int argc, char** argv);
int cmd_convert(int argc, char** argv);
int cmd_verify(int argc, char** argv);
int cmd_synth(int argc, char** argv);
int cmd_sample(int argc, char** argv);
int cmd_split(int argc, char** argv);
int cmd_hierarchy(int argc, char** argv);
int cmd_lod(int argc, char** argv);

/// The whole program: dispatch and exception -> exit code mapping.
int cli_main(int argc, char** argv);

}  // namespace meshless::cli
