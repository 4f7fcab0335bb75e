// parallax: the command line. Each subcommand lives in its own command_<name>.cpp.
#include <cstdio>
#include <exception>
#include <new>
#include <string>
#include <vector>

#include "commands.h"
#include "core/error.h"
#include "parallax_build_info.h"

int main(int argc, char** argv) {
  CLI::App app{"Parallax: a viewer and toolkit for massive 3D point clouds"};
  // `parallax --version`: the version, this build's features, how it was built (for bug reports).
  app.set_version_flag("--version", std::string("parallax ") + parallax::build_info::kVersion +
                                        "\nfeatures:\n" + parallax::build_info::kFeatures +
                                        "build: " + parallax::build_info::kBuild);
  app.require_subcommand(1);
  const std::vector<parallax::cli::Command> commands = {
      parallax::cli::addInfoCommand(app),    parallax::cli::addGenerateCommand(app),
      parallax::cli::addBenchCommand(app),   parallax::cli::addConvertCommand(app),
      parallax::cli::addRenderCommand(app),  parallax::cli::addViewCommand(app),
      parallax::cli::addPickCommand(app),    parallax::cli::addConvertTaskCommand(app),
      parallax::cli::addProcessCommand(app),
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
  } catch (const parallax::InputError& e) {
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
