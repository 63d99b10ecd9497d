// The commands of the `symba` tool. Each Register function adds a CLI11
// subcommand whose callback runs it and stores the exit code.
#ifndef SYMBA_SRC_TOOLS_COMMANDS_H_
#define SYMBA_SRC_TOOLS_COMMANDS_H_

#include <cmath>
#include <string>

#include <CLI/CLI.hpp>

void RegisterEvalCommand(CLI::App* app, int* exit_code);
void RegisterExportCommand(CLI::App* app, int* exit_code);
void RegisterImportCommand(CLI::App* app, int* exit_code);
void RegisterReplayCommand(CLI::App* app, int* exit_code);
void RegisterSimulateCommand(CLI::App* app, int* exit_code);

namespace symba::tools {

// A check for numeric options: the value must be finite. CLI11's
// PositiveNumber and NonNegativeNumber let "nan" through (every comparison
// with NaN is false), so they are combined with this one:
// ->check(CLI::PositiveNumber & FiniteNumber()).
inline CLI::Validator FiniteNumber() {
  return CLI::Validator(
      [](std::string& input) -> std::string {
        double value = 0.0;
        if (CLI::detail::lexical_cast(input, value) && !std::isfinite(value)) {
          return "Value " + input + " is not a finite number";
        }
        return std::string();
      },
      "FINITE");
}

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
