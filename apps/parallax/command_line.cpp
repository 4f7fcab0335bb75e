// The command line: every subcommand registered on one CLI11 app, the chosen one run, and its
// errors reported as `parallax: error: ...` with the exit status main() returns.
#include <cstdio>
#include <exception>
#include <new>
#include <string>
#include <vector>

#include "commands.h"
#include "core/error.h"
#include "io/point_format.h"
#include "parallax_build_info.h"

namespace parallax::cli {
namespace {

// --version's formats line, from the format table (io/point_format.h), so that a format added
// there is listed here too (a line written by hand in CMake had fallen behind: no LAZ, E57, PCD,
// PTX, PTS or COPC).
std::string formatsFeatureLine() {
  std::string line = "  formats:";
  const char* separator = " ";
  for (const PointFormatEntry* row : pointFormats()) {
    line += separator + row->name;
    separator = ", ";
  }
  return line + " (read and write); Potree 2.0 and COPC octrees (read and write)\n";
}

}  // namespace

int runCommandLine(int argc, char** argv) {
  CLI::App app{"Parallax: a viewer and toolkit for massive 3D point clouds"};
  // `parallax --version`: the version, this build's features, how it was built (for bug reports).
  app.set_version_flag("--version", std::string("parallax ") + build_info::kVersion +
                                        "\nfeatures:\n" + build_info::kFeatures +
                                        formatsFeatureLine() + "build: " + build_info::kBuild);
  app.require_subcommand(1);
  const std::vector<Command> commands = {
      addInfoCommand(app),    addGenerateCommand(app),    addBenchCommand(app),
      addConvertCommand(app), addRenderCommand(app),      addViewCommand(app),
      addPickCommand(app),    addConvertTaskCommand(app), addProcessCommand(app),
      addRasterCommand(app),  addVolumeCommand(app),      addRegisterCommand(app),
  };

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  try {
    for (const auto& command : commands) {
      if (command.subcommand->parsed()) return command.run();
    }
  } catch (const InputError& e) {
    std::fprintf(stderr, "parallax: error: %s\n", e.what());
    return 2;
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "parallax: error: out of memory\n");
    return 3;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "parallax: error: %s\n", e.what());
    return 1;
  }
  return 1;
}

}  // namespace parallax::cli
