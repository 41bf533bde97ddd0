// The meshless executable: everything lives in the meshless_cli library (cli/app.cpp).
#include "cli/commands.hpp"

int main(int argc, char** argv) { return meshless::cli::cli_main(argc, argv); }
