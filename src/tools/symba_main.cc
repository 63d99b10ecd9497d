// The `symba` command line. Each command parses its flags and calls the
// library (src/tools/*_command.cc); `symba <command> --help` lists every
// option with its default. Exit codes: 0 success, 1 failure (the message on
// stderr), 2 bad command line (CLI11's usage errors, e.g. 105, are
// returned as CLI11 reports them).
#include <CLI/CLI.hpp>

#include "tools/commands.h"

int main(int argc, char** argv) {
  CLI::App app{
      "symba: the estimation backend of object SLAM with symmetric objects"};
  app.require_subcommand(1);
  int exit_code = 0;
  symba::tools::RegisterCommands(&app, &exit_code);
  CLI11_PARSE(app, argc, argv);
  return exit_code;
}
