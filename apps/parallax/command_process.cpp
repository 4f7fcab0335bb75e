// `parallax process IN... -o OUT [STEP...]`: normals, outliers, subsampling and distances, the
// steps run in the order given, out of core within --memory (process/process_runner.h).
#include <CLI/CLI.hpp>

#include <cstdio>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "commands.h"
#include "filter_options.h"
#include "process/process_runner.h"
#include "progress_options.h"

namespace parallax::cli {

namespace {

struct ProcessArgs {
  std::vector<std::string> inputs;
  std::string output;
  std::uint64_t memory_mb = 2048;
  std::vector<std::string> columns;
  bool ascii = false;
  bool quiet = false;
  FilterOptions filter_options;
  // The step options, each occurrence one step; their order comes from CLI11's parse order.
  std::vector<std::string> normals, normals_radius, outliers, subsample, distance_to, ground;
  bool curvature = false;
  std::string orient = "up";
  bool mark_outliers = false;
  std::string local_model;
  std::uint32_t local_k = 6;
  bool keep_classes = false;
  bool height_above_ground = false;
  std::vector<std::string> m3c2;
  std::string core_points;
  double normal_scale = 0.0, cylinder_radius = 0.0, half_length = 0.0, registration_error = 0.0;
  bool m3c2_median = false;
  CLI::App* sub = nullptr;
};

std::vector<ProcessStep> stepsInOrder(const ProcessArgs& args) {
  std::map<std::string, std::size_t> taken;
  std::vector<ProcessStep> steps;
  for (const CLI::Option* option : args.sub->parse_order()) {
    const std::string name = option->get_name();
    auto next = [&](const std::vector<std::string>& values) { return values.at(taken[name]++); };
    if (name == "--normals") {
      NormalsStep step = parseNormalsK(next(args.normals));
      step.curvature = args.curvature;
      parseOrientation(args.orient, step);
      steps.push_back(step);
    } else if (name == "--normals-radius") {
      NormalsStep step = parseNormalsRadius(next(args.normals_radius));
      step.curvature = args.curvature;
      parseOrientation(args.orient, step);
      steps.push_back(step);
    } else if (name == "--outliers") {
      OutliersStep step = parseOutliers(next(args.outliers));
      step.mark = args.mark_outliers;
      steps.push_back(step);
    } else if (name == "--subsample") {
      steps.push_back(parseSubsample(next(args.subsample)));
    } else if (name == "--distance-to") {
      DistanceStep step;
      step.reference = next(args.distance_to);
      step.k = args.local_k;
      if (!args.local_model.empty()) parseLocalModel(args.local_model, step);
      steps.push_back(step);
    } else if (name == "--height-above-ground") {
      steps.push_back(HeightAboveGroundStep{});
    } else if (name == "--ground") {
      GroundStep step = parseGround(next(args.ground));
      step.keep_classes = args.keep_classes;
      steps.push_back(step);
    } else if (name == "--m3c2") {
      M3c2Step step;
      step.epoch2 = next(args.m3c2);
      // --core-points: the processed cloud is the core points, epoch 1 the inputs.
      if (!args.core_points.empty()) {
        for (const std::string& input : args.inputs) step.epoch1.emplace_back(input);
      }
      step.normal_scale = args.normal_scale;
      step.cylinder_radius = args.cylinder_radius;
      step.half_length = args.half_length;
      step.registration_error = args.registration_error;
      step.median = args.m3c2_median;
      NormalsStep orientation;
      parseOrientation(args.orient, orientation);
      step.orientation = orientation.orientation;
      for (int a = 0; a < 3; ++a) step.toward[a] = orientation.toward[a];
      checkM3c2(step);
      steps.push_back(step);
    }
  }
  return steps;
}

int runProcessCommand(const ProcessArgs& args) {
  ProcessOptions options;
  const PointFilter filter = pointFilterFrom(args.filter_options, FilterTarget::Cpu);
  if (!args.core_points.empty()) {
    if (args.m3c2.empty()) throw std::invalid_argument("--core-points: only with --m3c2");
    options.inputs.push_back({args.core_points, args.columns, filter});
  } else {
    for (const std::string& input : args.inputs)
      options.inputs.push_back({input, args.columns, filter});
  }
  options.output = args.output;
  options.steps = stepsInOrder(args);
  if (options.steps.empty()) {
    throw std::invalid_argument(
        "process: no step given (--normals K, --normals-radius R, --outliers, --subsample, "
        "--distance-to, --ground, --height-above-ground, --m3c2)");
  }
  options.memory_mb = args.memory_mb;
  options.write.ply_ascii = args.ascii;
  options.progress = stageBars(args.quiet);
  const ProcessReport report = runProcess(options);
  if (!args.quiet) {
    for (const std::string& loss : report.losses) {
      std::fprintf(stderr, "dropped or changed: %s\n", loss.c_str());
    }
    std::fprintf(stderr, "%llu points in, %llu written to %s (%zu tiles)\n",
                 static_cast<unsigned long long>(report.input_points),
                 static_cast<unsigned long long>(report.output_points), args.output.c_str(),
                 report.tiles);
  }
  return 0;
}

}  // namespace

Command addProcessCommand(CLI::App& app) {
  auto args = std::make_shared<ProcessArgs>();
  CLI::App* sub = app.add_subcommand(
      "process",
      "Normals, outlier removal, subsampling, distances to another cloud, ground "
      "classification, heights above ground and M3C2, the steps run in the order given, out of "
      "core within --memory; every other attribute is kept");
  args->sub = sub;
  sub->add_option(
         "input", args->inputs,
         "Input point files (PLY, LAS, LAZ, text) or Potree directories, read as one cloud")
      ->required();
  sub->add_option("-o,--output", args->output,
                  "Output point file, its extension picks the format (.ply .las .laz .xyz .txt "
                  ".csv .pts); PLY, LAS and LAZ are written as they go, text is held whole")
      ->required();
  sub->add_option(
      "--normals", args->normals,
      "Step: normals (nx ny nz, float) by PCA of the K nearest points, the point itself "
      "included (K 3-1000)");
  sub->add_option("--normals-radius", args->normals_radius,
                  "Step: normals by PCA of the points within R");
  sub->add_flag("--curvature", args->curvature,
                "Normals steps: also write curvature (float: lambda0 / (lambda0 + lambda1 + "
                "lambda2))");
  sub->add_option(
      "--orient", args->orient,
      "Normals and M3C2 steps: up (towards +z, default), X,Y,Z (towards a point), propagate "
      "(consistent along the surface: a minimum spanning tree over the K-nearest "
      "graph, Hoppe 1992; the cloud must fit --memory), sensor (towards the scanner: "
      "sensor_x/y/z, scanner_x/y/z or vp_x/y/z columns, E57 and PTX scans, a PCD "
      "VIEWPOINT)");
  sub->add_option("--outliers", args->outliers,
                  "Step: statistical:K,S (mean distance to the K nearest more than S standard "
                  "deviations above the cloud's mean, as PCL's StatisticalOutlierRemoval) or "
                  "radius:R,N (fewer than N other points within R) removed");
  sub->add_flag("--mark-outliers", args->mark_outliers,
                "Outlier steps: keep the outliers as class 7 (low noise) instead of removing them");
  sub->add_option("--subsample", args->subsample,
                  "Step: voxel:SIZE (one original point per occupied voxel, the nearest to the "
                  "voxel's centroid; voxels from the cloud's minimum corner), spacing:D (no two "
                  "kept points closer than D, greedily: columns of width D in x, input order "
                  "within one) or random:N (N points, uniformly; the same N points whatever "
                  "--memory)");
  sub->add_option("--distance-to", args->distance_to,
                  "Step: each point's distance (float 'distance') to its nearest point of this "
                  "reference cloud");
  sub->add_option("--local-model", args->local_model,
                  "Distance steps: plane (the distance to the plane of the --local-k nearest "
                  "reference points)");
  sub->add_option("--local-k", args->local_k,
                  "Distance steps: points of the local model (default 6)")
      ->check(CLI::Range(std::uint32_t(3), std::uint32_t(1000)));
  sub->add_option("--ground", args->ground,
                  "Step: ground classification, class 2 (ground) and 1 (the rest): "
                  "smrf[:cell=1,slope=0.15,window=18,scalar=1.25,threshold=0.5] (Pingel et al. "
                  "2013, PDAL's parameters and defaults), "
                  "pmf[:max_window_size=33,slope=0.7,initial_distance=0.15,max_distance=10,"
                  "cell_size=1,base=2,exponential=true] (Zhang et al. 2003, PCL's), "
                  "csf[:resolution=0.5,rigidness=3,iterations=500,time_step=0.65,"
                  "class_threshold=0.5,slope_smoothing=true] (Zhang et al. 2016, the CSF "
                  "library's); a grid of the cloud's extent must fit --memory");
  sub->add_flag("--keep-classes", args->keep_classes,
                "Ground steps: classify only points of class 0 or 1; the others (noise 7, "
                "buildings 6, ...) keep their class and stay out of the ground surface");
  sub->add_flag("--height-above-ground", args->height_above_ground,
                "Step: height_above_ground (float), z less the ground's under the point: a 2D "
                "Delaunay triangulation of the class 2 points (the input's or an earlier "
                "--ground's); outside their convex hull the nearest one's z");
  sub->add_option("--m3c2", args->m3c2,
                  "Step: M3C2 (Lague et al. 2013) from the input (epoch 1) to this cloud (epoch "
                  "2) at every core point: m3c2_distance, m3c2_uncertainty (LoD95), "
                  "m3c2_significant, m3c2_count1/2, m3c2_std1/2; needs --normal-radius, "
                  "--cylinder-radius, --cylinder-half-length; normals oriented by --orient (up "
                  "or X,Y,Z)");
  sub->add_option("--core-points", args->core_points,
                  "M3C2: the core points (a point file); the output is these points with the "
                  "m3c2 columns (default: every input point)");
  sub->add_option("--normal-radius", args->normal_scale,
                  "M3C2: the normal scale D, a diameter as in the paper (PCA of epoch 1 within "
                  "D/2)");
  sub->add_option("--cylinder-radius", args->cylinder_radius,
                  "M3C2: the projection cylinder's radius R (the paper's d = 2R)");
  sub->add_option("--cylinder-half-length", args->half_length,
                  "M3C2: the cylinder reaches H either side of the core point along the normal");
  sub->add_option("--registration-error", args->registration_error,
                  "M3C2: the registration error reg of the level of detection (default 0)");
  sub->add_flag("--m3c2-median", args->m3c2_median,
                "M3C2: medians of the epochs' projections instead of means");
  sub->add_option("--memory", args->memory_mb,
                  "Memory budget in MB for the tiles (default 2048); the output does not depend "
                  "on it")
      ->check(CLI::Range(std::uint64_t(1), std::uint64_t(1) << 24));
  sub->add_option("--columns", args->columns,
                  "Text input: the columns' names, e.g. x,y,z,r,g,b (_ skips a column)")
      ->delimiter(',');
  sub->add_flag("--ascii", args->ascii, "PLY output: ascii instead of binary little endian");
  addFilterOptions(*sub, args->filter_options, "processed");
  addQuietFlag(*sub, args->quiet);
  Command command;
  command.subcommand = sub;
  command.run = [args] { return runProcessCommand(*args); };
  return command;
}

}  // namespace parallax::cli
