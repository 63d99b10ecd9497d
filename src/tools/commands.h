// The commands of the `symba` tool. Each Register function adds a CLI11
// subcommand whose callback runs it and stores the exit code.
#ifndef SYMBA_SRC_TOOLS_COMMANDS_H_
#define SYMBA_SRC_TOOLS_COMMANDS_H_

#include <CLI/CLI.hpp>

void RegisterEvalCommand(CLI::App* app, int* exit_code);
void RegisterExportCommand(CLI::App* app, int* exit_code);
void RegisterImportCommand(CLI::App* app, int* exit_code);
void RegisterReplayCommand(CLI::App* app, int* exit_code);
void RegisterSimulateCommand(CLI::App* app, int* exit_code);

namespace symba::tools {

// Registers every command (add new ones here).
inline void RegisterCommands(CLI::App* app, int* exit_code) {
  RegisterReplayCommand(app, exit_code);
  RegisterSimulateCommand(app, exit_code);
  RegisterEvalCommand(app, exit_code);
  RegisterImportCommand(app, exit_code);
  RegisterExportCommand(app, exit_code);
}

}  // namespace symba::tools

#endif  // SYMBA_SRC_TOOLS_COMMANDS_H_
