// `parallax register SOURCE TARGET [-o ALIGNED] [--max-distance D] [--init FILE] [--json]`:
// point-to-plane ICP (registration/point_to_plane_icp.h), printing the transform that takes
// SOURCE's coordinates to TARGET's, the RMS and the overlap; -o writes the moved source.
#include <CLI/CLI.hpp>

#include <cstdio>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "commands.h"
#include "core/error.h"
#include "io/point_file.h"
#include "progress_options.h"
#include "registration/cloud_registration.h"
#include "registration/point_to_plane_icp.h"
#include "registration/rigid_transform.h"

namespace parallax::cli {

namespace {

struct RegisterArgs {
  std::string source, target, output, init;
  double max_distance = 0.0;
  std::uint32_t levels = 3, iterations = 100, normal_k = 16;
  bool json = false, quiet = false;
};

int runRegister(const RegisterArgs& args) {
  IcpOptions options;
  options.max_distance = args.max_distance;
  options.levels = args.levels;
  options.max_iterations = args.iterations;
  options.normal_k = args.normal_k;
  if (!args.init.empty()) options.init = readRigidTransform(args.init);
  PointCloud source = readPointFile(args.source);
  const PointCloud target = readPointFile(args.target);
  const IcpResult result = registerClouds(source, target, options, args.source, args.target);
  if (args.json) {
    nlohmann::json out;
    out["transform"] = nlohmann::json::array();
    for (const auto& row : result.transform.m) out["transform"].push_back(row);
    out["rms"] = result.rms;
    out["overlap"] = result.overlap;
    out["correspondences"] = result.correspondences;
    out["iterations"] = result.iterations;
    out["max_distance"] = result.max_distance;
    std::printf("%s\n", out.dump().c_str());
  } else {
    std::printf("transform (%s -> %s):\n%s", args.source.c_str(), args.target.c_str(),
                formatRigidTransform(result.transform).c_str());
    std::printf("rotation %.6g degrees, translation %.6g\n", result.transform.angleDegrees(),
                result.transform.translationLength());
    std::printf("rms %.9g\noverlap %.6f (%llu of %zu source points within %.6g)\n", result.rms,
                result.overlap, static_cast<unsigned long long>(result.correspondences),
                std::size_t(source.count), result.max_distance);
  }
  if (!args.output.empty()) {
    transformCloud(source, result.transform);
    writePointFile(source, args.output);
    if (!args.quiet) std::fprintf(stderr, "wrote %s\n", args.output.c_str());
  }
  return 0;
}

}  // namespace

Command addRegisterCommand(CLI::App& app) {
  auto args = std::make_shared<RegisterArgs>();
  CLI::App* sub = app.add_subcommand(
      "register",
      "Align SOURCE to TARGET by point-to-plane ICP, coarse to fine: prints the 4x4 transform "
      "taking SOURCE's coordinates to TARGET's, the RMS and the overlap");
  sub->add_option("source", args->source, "The cloud to move (any point file Parallax reads)")
      ->required();
  sub->add_option("target", args->target, "The cloud it is aligned to")->required();
  sub->add_option("-o,--output", args->output,
                  "Write the moved source here (every attribute kept, normals rotated; the "
                  "extension picks the format)");
  sub->add_option("--max-distance", args->max_distance,
                  "Pairs farther apart than this are ignored (default: a twentieth of the "
                  "target's bounding box diagonal)")
      ->check(CLI::PositiveNumber);
  sub->add_option("--init", args->init,
                  "A 4x4 matrix (four lines of four numbers) to start from, SOURCE -> TARGET");
  sub->add_option("--levels", args->levels,
                  "Coarse-to-fine levels (voxel centroids of the source, the last every point; "
                  "default 3)")
      ->check(CLI::Range(1, 12));
  sub->add_option("--iterations", args->iterations, "At most this many iterations a level (100)")
      ->check(CLI::Range(1, 10000));
  sub->add_option("--normal-k", args->normal_k,
                  "Target normals by PCA of this many nearest points when the target has none "
                  "(16)")
      ->check(CLI::Range(3, 1000));
  sub->add_flag("--json", args->json,
                "Print {\"transform\": [[4 rows of 4]], \"rms\": .., \"overlap\": .., ...}");
  addQuietFlag(*sub, args->quiet);
  Command command;
  command.subcommand = sub;
  command.run = [args] { return runRegister(*args); };
  return command;
}

}  // namespace parallax::cli
