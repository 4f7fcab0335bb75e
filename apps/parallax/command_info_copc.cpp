#include "command_info_copc.h"

#include "info_json.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "io/las_header.h"
#include "lod/copc_reader.h"
#include "lod/octree_open.h"

namespace parallax::cli {
namespace {

using Json = InfoJson;

std::string text(const std::array<double, 3>& v) {
  char out[128];
  std::snprintf(out, sizeof out, "(%.10g, %.10g, %.10g)", v[0], v[1], v[2]);
  return out;
}

struct Level {
  std::size_t nodes = 0;
  std::uint64_t points = 0;
};

}  // namespace

int runCopcInfo(const std::filesystem::path& path, bool json) {
  const auto start = std::chrono::steady_clock::now();
  std::unique_ptr<Octree> octree = openOctree(path);  // a file or its URL
  // Every page, so that the counts are the whole tree's (expanding appends).
  for (std::size_t i = 0; i < octree->nodes().size(); ++i) {
    if (octree->nodes()[i].hierarchy_pending) octree->expandHierarchy(std::int32_t(i));
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const CopcDetails details = *copcDetails(*octree);
  const OctreeInfo& info = octree->info();
  const LasHeader& header = details.header;
  std::vector<Level> levels;
  std::size_t empty_nodes = 0;
  for (const OctreeNode& node : octree->nodes()) {
    if (levels.size() <= std::size_t(node.level)) levels.resize(std::size_t(node.level) + 1);
    ++levels[std::size_t(node.level)].nodes;
    levels[std::size_t(node.level)].points += node.point_count;
    empty_nodes += node.point_count == 0 ? 1 : 0;
  }
  const CopcInfo& v = details.info;

  if (json) {
    Json per_level = Json::array();
    for (std::size_t l = 0; l < levels.size(); ++l) {
      per_level.push_back({{"level", l},
                           {"nodes", levels[l].nodes},
                           {"points", levels[l].points},
                           {"spacing", v.spacing / double(std::uint64_t{1} << l)}});
    }
    const Json out = {
        {"file", path.string()},
        {"file_bytes", details.file_bytes},
        {"format", "copc"},
        {"format_details",
         {{"las_version", header.versionString()},
          {"point_format", header.point_format},
          {"record_bytes", header.record_length},
          {"chunks", details.chunks},
          {"info",
           {{"center", jsonTriple(v.center)},
            {"halfsize", finiteOrNull(v.halfsize)},
            {"spacing", finiteOrNull(v.spacing)},
            {"root_hierarchy_offset", v.root_hierarchy_offset},
            {"root_hierarchy_size", v.root_hierarchy_size},
            {"gps_time_min", finiteOrNull(v.gps_time_min)},
            {"gps_time_max", finiteOrNull(v.gps_time_max)}}},
          {"hierarchy",
           {{"pages", details.pages_read},
            {"nodes", octree->nodes().size()},
            {"empty_nodes", empty_nodes},
            {"depth", levels.empty() ? 0 : int(levels.size()) - 1},
            {"levels", per_level}}},
          {"crs", header.crs.summary()},
          {"generating_software", header.generating_software}}},
        {"points", info.point_count},
        {"bounds", {{"min", jsonTriple(info.bounds.min)}, {"max", jsonTriple(info.bounds.max)}}},
        {"cube", {{"min", jsonTriple(info.cube.min)}, {"max", jsonTriple(info.cube.max)}}},
        {"quantization",
         {{"scale", jsonTriple(info.quantization.scale)},
          {"offset", jsonTriple(info.quantization.offset)}}},
        {"attributes", info.attributes},
        {"load_seconds", seconds},
    };
    std::puts(out.dump(2).c_str());
    return 0;
  }
  std::printf("file          %s (%llu bytes, %.1f MB)\n", path.c_str(),
              static_cast<unsigned long long>(details.file_bytes), details.file_bytes / 1e6);
  std::printf(
      "format        COPC 1.0: LAS %s, point format %d (%u-byte records), LAZ layered, "
      "%llu chunks\n",
      header.versionString().c_str(), header.point_format, unsigned(header.record_length),
      static_cast<unsigned long long>(details.chunks));
  std::printf("info VLR      center %s, halfsize %.10g, spacing %.10g\n", text(v.center).c_str(),
              v.halfsize, v.spacing);
  std::printf(
      "              root hierarchy page at byte %llu (%llu bytes), GPS time %.10g .. "
      "%.10g\n",
      static_cast<unsigned long long>(v.root_hierarchy_offset),
      static_cast<unsigned long long>(v.root_hierarchy_size), v.gps_time_min, v.gps_time_max);
  std::printf("hierarchy     %zu pages, %zu nodes (%zu without points), depth %d\n",
              details.pages_read, octree->nodes().size(), empty_nodes,
              levels.empty() ? 0 : int(levels.size()) - 1);
  for (std::size_t l = 0; l < levels.size(); ++l) {
    std::printf("  level %2zu    %7zu nodes %12llu points, spacing %.6g\n", l, levels[l].nodes,
                static_cast<unsigned long long>(levels[l].points),
                v.spacing / double(std::uint64_t{1} << l));
  }
  std::printf("points        %llu\n", static_cast<unsigned long long>(info.point_count));
  std::printf("bounds        min %s\n", text(info.bounds.min).c_str());
  std::printf("              max %s\n", text(info.bounds.max).c_str());
  std::printf("cube          min %s\n", text(info.cube.min).c_str());
  std::printf("              max %s\n", text(info.cube.max).c_str());
  std::printf("quantization  scale %s offset %s\n", text(info.quantization.scale).c_str(),
              text(info.quantization.offset).c_str());
  std::printf("CRS           %s\n", header.crs.summary().c_str());
  std::printf("attributes   ");
  for (const auto& name : info.attributes) std::printf(" %s", name.c_str());
  std::printf("\nopen          %.3f s (header, chunk table and the whole hierarchy)\n", seconds);
  return 0;
}

}  // namespace parallax::cli
