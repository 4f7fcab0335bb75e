// placeholder: being written
#include "commands.h"

namespace parallax::cli {

Command addInfoCommand(CLI::App& app) {
  Command command;
  command.subcommand = app.add_subcommand("info", "(being written)");
  command.run = [] { return 1; };
  return command;
}

}  // namespace parallax::cli
