// `parallax convert --plan` and `parallax convert-task` (convert_task.h).
#include <tbb/global_control.h>

#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <thread>

#include "convert_task.h"
#include "core/error.h"
#include "lod/distributed_plan.h"
#include "lod/distributed_task_files.h"
#include "lod/distributed_tasks.h"
#include "lod/potree_converter.h"

namespace parallax::cli {
namespace {

// The filter options as the plan keeps them: every option's text, the polygon file's path made
// absolute (the workers may run in another directory; the work directory is shared).
nlohmann::json filterJson(const FilterOptions& options) {
  const std::string polygon =
      options.clip_polygon.empty() ? "" : std::filesystem::absolute(options.clip_polygon).string();
  return {{"classes", options.classes},     {"returns", options.returns},
          {"intensity", options.intensity}, {"elevation", options.elevation},
          {"gps_time", options.gps_time},   {"clip_box", options.clip_box},
          {"clip_polygon", polygon},        {"clip_mode", options.clip_mode}};
}

FilterOptions filterOptionsFrom(const nlohmann::json& json, const std::string& plan_path) {
  try {
    return {.classes = json.at("classes").get<std::string>(),
            .returns = json.at("returns").get<std::string>(),
            .intensity = json.at("intensity").get<std::string>(),
            .elevation = json.at("elevation").get<std::string>(),
            .gps_time = json.at("gps_time").get<std::string>(),
            .clip_box = json.at("clip_box").get<std::string>(),
            .clip_polygon = json.at("clip_polygon").get<std::string>(),
            .clip_mode = json.at("clip_mode").get<std::string>()};
  } catch (const nlohmann::json::exception& e) {
    throw InputError({.file = plan_path,
                      .element = "filter",
                      .expected =
                          "the filter options (classes, returns, intensity, elevation, gps_time, "
                          "clip_box, clip_polygon, clip_mode)",
                      .found = e.what(),
                      .hint = "write the plan again with parallax convert --plan"});
  }
}

struct TaskArgs {
  std::string stage;
  std::string plan;
  std::size_t part = 0;
  int threads = 1;
};

int runConvertTask(const TaskArgs& args) {
  // One thread by default: a Dask worker runs one task per thread it has, so the cores are
  // shared out by the cluster, not by each task.
  std::optional<tbb::global_control> threads;
  if (args.threads > 0) {
    threads.emplace(tbb::global_control::max_allowed_parallelism, std::size_t(args.threads));
  }
  const DistributedPlan plan = readDistributedPlan(args.plan);
  const PointFilter filter =
      pointFilterFrom(filterOptionsFrom(plan.filter, args.plan), FilterTarget::Cpu);
  std::vector<ConvertInput> inputs;
  for (const PlannedInput& input : plan.inputs) {
    inputs.push_back({input.path, plan.text_columns, filter});
  }
  const std::string summary = runDistributedTask(plan, inputs, args.stage, args.part);
  std::printf("%s\n", summary.c_str());
  return 0;
}

}  // namespace

int runConvertPlan(const ConvertPlanRequest& request) {
  const PointFilter filter = pointFilterFrom(request.filter_options, FilterTarget::Cpu);
  std::vector<ConvertInput> inputs;
  for (const std::string& input : request.inputs) {
    inputs.push_back({input, request.columns, filter});
  }
  std::filesystem::path output = std::filesystem::absolute(request.output).lexically_normal();
  if (!output.has_filename()) output = output.parent_path();
  checkPotreeOutput(output);
  const std::filesystem::path work_dir =
      request.work_dir.empty() ? output.parent_path() / ("." + output.filename().string() + ".work")
                               : std::filesystem::path(request.work_dir);
  const std::size_t tasks =
      request.tasks > 0 ? request.tasks : 4 * std::max(1u, std::thread::hardware_concurrency());
  DistributedPlan plan = makeDistributedPlan(inputs, output, work_dir, request.build, tasks);
  if (request.build_tasks > 0) plan.build_tasks = request.build_tasks;
  plan.filter = filterJson(request.filter_options);
  clearTaskFiles(plan.work_dir);
  writeDistributedPlan(plan);
  std::printf("{\"plan\": %s, \"ranges\": %zu, \"build_tasks\": %zu}\n",
              nlohmann::json(planPath(plan.work_dir).string()).dump().c_str(), plan.ranges.size(),
              plan.build_tasks);
  if (!request.quiet) {
    std::fprintf(stderr, "wrote %s: %zu inputs in %zu ranges, up to %zu build tasks\n",
                 planPath(plan.work_dir).c_str(), plan.inputs.size(), plan.ranges.size(),
                 plan.build_tasks);
  }
  return 0;
}

Command addConvertTaskCommand(CLI::App& app) {
  auto args = std::make_shared<TaskArgs>();
  Command command;
  CLI::App* sub = app.add_subcommand(
      "convert-task",
      "Run one task of a distributed octree conversion (plan.json from parallax convert --plan): "
      "scan, count and distribute take a range (--part), build and place a group of chunks, "
      "cube, chunks and finish merge; each reads files of the plan's work directory and writes its "
      "own under "
      "a temporary name, renamed when complete");
  sub->add_option("stage", args->stage,
                  "scan, cube, count, chunks, distribute, build, place or finish (in this order)")
      ->required()
      ->check(CLI::IsMember(
          {"scan", "cube", "count", "chunks", "distribute", "build", "place", "finish"}));
  sub->add_option("plan", args->plan, "The plan (WORK/plan.json)")->required();
  sub->add_option("--part", args->part, "The range or group (from 0; default 0)");
  sub->add_option("--threads", args->threads, "Worker threads (default 1; 0: every core)")
      ->check(CLI::NonNegativeNumber);
  command.subcommand = sub;
  command.run = [args] { return runConvertTask(*args); };
  return command;
}

}  // namespace parallax::cli
