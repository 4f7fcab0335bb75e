// placeholder: being written
#include "commands.h"

namespace parallax::cli {

Command addBenchCommand(CLI::App& app) {
  Command command;
  command.subcommand = app.add_subcommand("bench", "(being written)");
  command.run = [] { return 1; };
  return command;
}

}  // namespace parallax::cli
