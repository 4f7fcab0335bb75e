// DistributedPlan (distributed_plan.h): the inputs' headers, their ranges, plan.json.
#include "lod/distributed_plan.h"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "core/error.h"
#include "io/coordinate_system.h"

namespace parallax {
namespace {

constexpr const char* kPlanFormat = "parallax-convert-plan";
constexpr int kPlanVersion = 1;

nlohmann::json quantizationJson(const Quantization& q) {
  return {{"scale", q.scale}, {"offset", q.offset}};
}

Quantization quantizationFrom(const nlohmann::json& json) {
  Quantization q;
  q.scale = json.at("scale").get<std::array<double, 3>>();
  q.offset = json.at("offset").get<std::array<double, 3>>();
  return q;
}

// Ranges of about `target` points; an input that cannot be split is one range.
std::vector<InputRange> splitInputs(const std::vector<PlannedInput>& inputs, std::size_t tasks) {
  std::uint64_t total = 0;
  for (const PlannedInput& input : inputs) total += input.points;
  const std::uint64_t target = std::max<std::uint64_t>(1, (total + tasks - 1) / tasks);
  std::vector<InputRange> ranges;
  for (std::size_t i = 0; i < inputs.size(); ++i) {
    const std::uint64_t points = inputs[i].points;
    const std::uint64_t pieces =
        inputs[i].splittable ? std::max<std::uint64_t>(1, (points + target / 2) / target) : 1;
    for (std::uint64_t k = 0; k < pieces; ++k) {
      // Even pieces, the remainder spread over them: [points * k / pieces, points * (k+1) / pieces).
      const auto at = [&](std::uint64_t j) {
        return points / pieces * j + points % pieces * j / pieces;  // no overflow
      };
      ranges.push_back({.input = i, .first = at(k), .last = at(k + 1)});
    }
  }
  return ranges;
}

}  // namespace

std::filesystem::path temporaryPathFor(const std::filesystem::path& path) {
  static std::atomic<unsigned> counter{0};
  // Appended piece by piece: GCC 12 warns (-Wrestrict, wrongly) on one chain of `+`.
  std::string name = ".";
  name.append(path.filename().string());
  name.append(".tmp-");
  name.append(std::to_string(::getpid()));
  name.push_back('-');
  name.append(std::to_string(counter++));
  return path.parent_path() / name;
}

void writeFileAtomically(const std::filesystem::path& path, std::string_view bytes) {
  const std::filesystem::path temp = temporaryPathFor(path);
  {
    std::ofstream out(temp, std::ios::binary);
    out.write(bytes.data(), std::streamsize(bytes.size()));
    out.close();
    if (!out) {
      std::error_code ignored;
      std::filesystem::remove(temp, ignored);
      throw std::runtime_error(temp.string() + ": cannot write: " + std::strerror(errno));
    }
  }
  std::filesystem::rename(temp, path);
}

std::string readWholeFile(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    throw std::runtime_error(path.string() +
                             ": cannot open (the task that writes it has not run, or failed)");
  }
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw std::runtime_error(path.string() + ": cannot read");
  return std::move(text).str();
}

std::filesystem::path planPath(const std::filesystem::path& work_dir) {
  return work_dir / "plan.json";
}

DistributedPlan makeDistributedPlan(const std::vector<ConvertInput>& inputs,
                                    const std::filesystem::path& output,
                                    const std::filesystem::path& work_dir,
                                    const OctreeBuildOptions& build, std::size_t tasks) {
  DistributedPlan plan;
  plan.work_dir = std::filesystem::absolute(work_dir).lexically_normal();
  plan.output = std::filesystem::absolute(output).lexically_normal();
  if (!plan.output.has_filename()) plan.output = plan.output.parent_path();
  plan.build = build;
  plan.build.progress = nullptr;
  plan.build_tasks = std::max<std::size_t>(1, tasks);
  if (!inputs.empty()) plan.text_columns = inputs.front().text_columns;
  CoordinateSystem crs;
  std::filesystem::path crs_source;
  for (const ConvertInput& input : inputs) {
    // Unfiltered: the first point gives the file's attributes, whatever the filter keeps.
    PointStream stream(input.path, input.text_columns);
    PlannedInput planned{.path = std::filesystem::absolute(input.path).lexically_normal(),
                         .points = stream.pointCount(),
                         .quantization = stream.quantization(),
                         .splittable = stream.canSkip()};
    PointCloud first;
    stream.next(first, 1);  // (an input without points has no layout the build uses)
    planned.layout = PotreeLayout::fromCloud(first);
    // The same check, with the same message, as the local scan (convert_count.cpp).
    const CoordinateSystem& own = stream.crs();
    if (!own.empty()) {
      if (crs.empty()) {
        crs = own;
        crs_source = input.path;
      } else if (!crs.sameAs(own)) {
        throw InputError({.file = input.path.string(),
                          .expected = "the coordinate reference system of " + crs_source.string() +
                                      " (" + crs.summary() + ")",
                          .found = own.summary(),
                          .hint = "inputs in different coordinate systems cannot be merged into "
                                  "one octree: reproject them first (e.g. pdal translate with "
                                  "filters.reprojection)"});
      }
    }
    plan.inputs.push_back(std::move(planned));
  }
  plan.projection = potreeProjection(crs.description);
  plan.ranges = splitInputs(plan.inputs, std::max<std::size_t>(1, tasks));
  return plan;
}

std::uint64_t jsonCount(const nlohmann::json& value, std::uint64_t max) {
  if (!value.is_number_unsigned() || value.get<std::uint64_t>() > max) {
    // A JSON type error, as a wrong type is: the readers name the file when they catch it.
    throw nlohmann::json::type_error::create(
        302, value.dump() + " where a whole number from 0 to " + std::to_string(max) + " belongs",
        &value);
  }
  return value.get<std::uint64_t>();
}

void writeDistributedPlan(const DistributedPlan& plan) {
  nlohmann::json inputs = nlohmann::json::array();
  for (const PlannedInput& input : plan.inputs) {
    inputs.push_back({{"path", input.path.string()},
                      {"points", input.points},
                      {"quantization", quantizationJson(input.quantization)},
                      {"layout", input.layout.toPlanJson()},
                      {"splittable", input.splittable}});
  }
  nlohmann::json ranges = nlohmann::json::array();
  for (const InputRange& range : plan.ranges) {
    ranges.push_back({range.input, range.first, range.last});
  }
  const nlohmann::json json = {{"format", kPlanFormat},
                               {"version", kPlanVersion},
                               {"work_dir", plan.work_dir.string()},
                               {"output", plan.output.string()},
                               {"inputs", inputs},
                               {"text_columns", plan.text_columns},
                               {"filter", plan.filter},
                               {"build",
                                {{"sampling", samplingMethodName(plan.build.sampling)},
                                 {"spacing", plan.build.spacing},
                                 {"max_node_points", plan.build.max_node_points},
                                 {"memory_bytes", plan.build.memory_bytes},
                                 {"max_chunk_points", plan.build.max_chunk_points}}},
                               {"projection", plan.projection},
                               {"ranges", ranges},
                               {"build_tasks", plan.build_tasks}};
  std::filesystem::create_directories(plan.work_dir);
  writeFileAtomically(planPath(plan.work_dir), json.dump(2) + "\n");
}

DistributedPlan readDistributedPlan(const std::filesystem::path& path) {
  std::string text;
  try {
    text = readWholeFile(path);
  } catch (const std::runtime_error&) {
    throw InputError({.file = path.string(),
                      .expected = "a conversion plan (plan.json)",
                      .found = "no readable file",
                      .hint = "write it first with parallax convert --plan IN... -o OUT"});
  }
  DistributedPlan plan;
  try {
    const nlohmann::json json = nlohmann::json::parse(text);
    if (json.at("format") != kPlanFormat || json.at("version") != kPlanVersion) {
      throw std::runtime_error("another format or version");
    }
    plan.work_dir = json.at("work_dir").get<std::string>();
    plan.output = json.at("output").get<std::string>();
    for (const nlohmann::json& input : json.at("inputs")) {
      plan.inputs.push_back(
          {.path = input.at("path").get<std::string>(),
           .points = jsonCount(input.at("points")),
           .quantization = quantizationFrom(input.at("quantization")),
           .layout = PotreeLayout::fromPlanJson(input.at("layout"), path.string()),
           .splittable = input.at("splittable").get<bool>()});
    }
    plan.text_columns = json.at("text_columns").get<std::vector<std::string>>();
    plan.filter = json.at("filter");
    const nlohmann::json& build = json.at("build");
    if (!parseSamplingMethod(build.at("sampling").get<std::string>(), plan.build.sampling)) {
      throw std::runtime_error("an unknown sampling method");
    }
    plan.build.spacing = build.at("spacing").get<double>();
    plan.build.max_node_points = std::uint32_t(jsonCount(build.at("max_node_points"), UINT32_MAX));
    plan.build.memory_bytes = jsonCount(build.at("memory_bytes"));
    plan.build.max_chunk_points = jsonCount(build.at("max_chunk_points"));
    plan.projection = json.at("projection").get<std::string>();
    for (const nlohmann::json& range : json.at("ranges")) {
      const InputRange r{.input = std::size_t(jsonCount(range.at(0))),
                         .first = jsonCount(range.at(1)),
                         .last = jsonCount(range.at(2))};
      if (r.input >= plan.inputs.size() || r.first > r.last ||
          r.last > plan.inputs[r.input].points ||
          (r.first > 0 && !plan.inputs[r.input].splittable)) {
        throw std::runtime_error("a range outside its input");
      }
      plan.ranges.push_back(r);
    }
    plan.build_tasks = std::max<std::size_t>(1, std::size_t(jsonCount(json.at("build_tasks"))));
  } catch (const std::exception& e) {
    throw InputError({.file = path.string(),
                      .expected = std::string("a conversion plan (") + kPlanFormat + " version " +
                                  std::to_string(kPlanVersion) + ")",
                      .found = e.what(),
                      .hint = "write it again with parallax convert --plan"});
  }
  return plan;
}

}  // namespace parallax
