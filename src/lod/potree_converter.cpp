#include "lod/potree_converter.h"

#include <tbb/global_control.h>

#include <chrono>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>

#include "core/error.h"
#include "io/coordinate_system.h"
#include "io/partial_output.h"

namespace parallax {
namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

void writeFile(const std::filesystem::path& path, const void* data, std::size_t size) {
  std::ofstream out(path, std::ios::binary);
  out.write(static_cast<const char*>(data), std::streamsize(size));
  out.close();
  if (!out) throw std::runtime_error(path.string() + ": cannot write");
}

}  // namespace

TemporaryDirectory::TemporaryDirectory(std::filesystem::path path) : path_(std::move(path)) {
  std::filesystem::remove_all(path_);
  std::filesystem::create_directories(path_);
}

TemporaryDirectory::~TemporaryDirectory() {
  if (!released_) {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
}

void checkPotreeOutput(const std::filesystem::path& output) {
  if (!std::filesystem::exists(output)) return;
  const bool potree =
      std::filesystem::is_directory(output) && std::filesystem::exists(output / "metadata.json");
  const bool empty_dir = std::filesystem::is_directory(output) && std::filesystem::is_empty(output);
  if (!potree && !empty_dir) {
    throw InputError(
        {.file = output.string(),
         .expected = "a new directory, an empty one, or a Potree directory to replace",
         .found = std::filesystem::is_directory(output) ? "a directory with other files" : "a file",
         .hint = "choose another output name or remove it"});
  }
}

std::filesystem::path partialPathFor(const std::filesystem::path& target) {
  return partialOutputPath(target);  // one naming for every writer (io/partial_output.h)
}

std::string potreeMetadataText(const PotreeMetadataFields& f) {
  const nlohmann::json json = {
      {"version", "2.0"},
      {"name", f.name},
      {"description", ""},
      {"points", f.points},
      {"projection", f.projection},
      {"hierarchy", {{"firstChunkSize", f.first_chunk_size}, {"stepSize", 4}, {"depth", f.depth}}},
      {"offset", f.quantization.offset},
      {"scale", f.quantization.scale},
      {"spacing", f.spacing},
      {"boundingBox", {{"min", f.cube.min}, {"max", f.cube.max}}},
      {"encoding", "DEFAULT"},
      {"attributes", f.layout->toJson(*f.stats)}};
  return json.dump(2);
}

EncodedHierarchy writePotreeIndex(const ConvertPlan& plan, std::vector<PotreeNodeEntry>& entries,
                                  const std::string& name, const std::string& projection,
                                  TemporaryDirectory& temp, const std::filesystem::path& target) {
  const std::int32_t root = linkPotreeNodes(entries);
  EncodedHierarchy hierarchy = encodePotreeHierarchy(entries, root);
  writeFile(temp.path() / "hierarchy.bin", hierarchy.bytes.data(), hierarchy.bytes.size());
  const std::string metadata = potreeMetadataText({.points = plan.points,
                                                   .quantization = plan.quantization,
                                                   .spacing = plan.spacing,
                                                   .cube = plan.cube,
                                                   .layout = &plan.layout,
                                                   .stats = &plan.stats,
                                                   .first_chunk_size = hierarchy.first_chunk_size,
                                                   .depth = hierarchy.depth,
                                                   .name = name,
                                                   .projection = projection});
  // metadata.json last: a directory without it is never taken for a finished octree.
  writeFile(temp.path() / "metadata.json", metadata.data(), metadata.size());

  if (std::filesystem::exists(target)) std::filesystem::remove_all(target);
  std::filesystem::rename(temp.path(), target);
  temp.release();
  return hierarchy;
}

PotreeConvertResult convertToPotree(const std::vector<ConvertInput>& inputs,
                                    const std::filesystem::path& output,
                                    const PotreeConvertOptions& options) {
  const auto start = Clock::now();
  std::optional<tbb::global_control> threads;
  if (options.build.threads > 0) {
    threads.emplace(tbb::global_control::max_allowed_parallelism,
                    std::size_t(options.build.threads));
  }
  std::filesystem::path target = std::filesystem::absolute(output).lexically_normal();
  if (!target.has_filename()) target = target.parent_path();
  checkPotreeOutput(target);
  std::filesystem::create_directories(target.parent_path());
  PotreeConvertResult result;
  // What killed conversions to the same target left behind (partial_output.h), before this one
  // needs the space.
  result.cleanup = removeStalePartialOutputs(target);
  TemporaryDirectory temp(partialOutputPath(target));

  auto mark = Clock::now();
  // The decoded points of slow inputs are kept under the temporary directory, so that any
  // failure removes them with it.
  ConvertPlan plan = scanInputs(inputs, options.build, options.progress, temp.path() / "decoded");
  for (const auto& spill : plan.spills) {
    if (!spill) continue;
    result.kept_points += spill->points();
    result.kept_memory_bytes += spill->memoryBytes();
    result.kept_file_bytes += spill->fileBytes();
  }
  result.seconds_scan = secondsSince(mark);
  mark = Clock::now();
  countChunks(plan, inputs, options.progress);
  result.seconds_count = secondsSince(mark);
  mark = Clock::now();
  const auto chunk_dir = temp.path() / "chunks";
  distributePoints(plan, inputs, chunk_dir, options.progress);
  // The last pass over the inputs is done: their kept points (memory and scratch files) go
  // before the build needs the memory.
  plan.spills.clear();
  std::filesystem::remove_all(temp.path() / "decoded");
  result.seconds_distribute = secondsSince(mark);

  mark = Clock::now();
  const auto sampler = makeSampler(options.build.sampling);
  OctreeBinWriter octree(temp.path() / "octree.bin", options.fail_after_octree_bytes);
  std::vector<PotreeNodeEntry> entries;
  std::vector<ChunkRoot> roots =
      buildChunks(plan, chunk_dir, options.build, *sampler, octree, entries, options.progress);
  throwIfBuildCancelled(options.build.cancel);
  buildTopLevels(plan, roots, *sampler, octree, entries);
  if (entries.empty()) entries.push_back({.name = "r"});  // an empty input: a root, no points
  octree.close();
  std::filesystem::remove_all(chunk_dir);
  result.seconds_build = secondsSince(mark);

  const std::string name = options.name.empty() ? target.filename().string() : options.name;
  throwIfBuildCancelled(options.build.cancel);
  const EncodedHierarchy hierarchy =
      writePotreeIndex(plan, entries, name, potreeProjection(plan.crs.description), temp, target);
  result.points = plan.points;
  result.crs = plan.crs;
  result.nodes = entries.size();
  result.chunks = plan.chunks.size();
  result.depth = hierarchy.depth;
  result.octree_bytes = octree.size();
  result.seconds_total = secondsSince(start);
  return result;
}

}  // namespace parallax
