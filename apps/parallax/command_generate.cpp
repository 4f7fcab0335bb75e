// placeholder: being written
#include "commands.h"

namespace parallax::cli {

Command addGenerateCommand(CLI::App& app) {
  Command command;
  command.subcommand = app.add_subcommand("generate", "(being written)");
  command.run = [] { return 1; };
  return command;
}

}  // namespace parallax::cli
