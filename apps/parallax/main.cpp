// parallax: the command line. Each subcommand lives in its own command_<name>.cpp; the app that
// registers and runs them is command_line.cpp.
#include "commands.h"

int main(int argc, char** argv) {
  return parallax::cli::runCommandLine(argc, argv);
}
