// The subcommands of `parallax`: each registers its options on the CLI11 app and runs when chosen.
// Each returns the process exit status; errors in input are reported on stderr by main.
#pragma once

#include <CLI/CLI.hpp>

#include <functional>

namespace parallax::cli {

// A registered subcommand; `run` is called after parsing when it was chosen and returns the exit
// code. Options are bound to state owned by `run` (captured shared state).
struct Command {
  CLI::App* subcommand = nullptr;
  std::function<int()> run;
};

// `parallax ARGS...`: parses argv, runs the chosen subcommand and returns the exit status (2 for
// bad input, 3 out of memory, 1 other errors), errors reported on stderr.
int runCommandLine(int argc, char** argv);

Command addInfoCommand(CLI::App& app);
Command addGenerateCommand(CLI::App& app);
Command addBenchCommand(CLI::App& app);
Command addConvertCommand(CLI::App& app);
Command addRenderCommand(CLI::App& app);
Command addViewCommand(CLI::App& app);
Command addPickCommand(CLI::App& app);
// `process` (command_process.cpp).
Command addProcessCommand(CLI::App& app);
// `register` (command_register.cpp).
Command addRegisterCommand(CLI::App& app);
// `raster` (command_raster.cpp).
Command addRasterCommand(CLI::App& app);
// `volume` (command_volume.cpp).
Command addVolumeCommand(CLI::App& app);
// `convert-task` (command_convert_task.cpp, convert_task.h).
Command addConvertTaskCommand(CLI::App& app);
// `bench render` (bench_render.cpp), registered by addBenchCommand.
Command addBenchRenderCommand(CLI::App& bench);
// `bench convert` (command_bench_convert.cpp), registered by addBenchCommand.
Command addBenchConvertCommand(CLI::App& bench);
// `bench laz` (command_bench_laz.cpp), registered by addBenchCommand.
Command addBenchLazCommand(CLI::App& bench);
// `bench register` (command_bench_register.cpp), registered by addBenchCommand.
Command addBenchRegisterCommand(CLI::App& bench);
// `bench normals` (command_bench_normals.cpp), registered by addBenchCommand.
Command addBenchNormalsCommand(CLI::App& bench);

}  // namespace parallax::cli
