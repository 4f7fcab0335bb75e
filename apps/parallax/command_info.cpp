// `parallax info FILE [--json]`: what a point file holds and how fast it loads.
//
// The file is read whole with readPointFile (the same path every command uses), timed, and then
// described: the format's own view (for PLY the header: encoding, version, comments, every
// element with its count and typed properties), the point count, the bounds in world
// coordinates, the quantization, and the min/max of every attribute. `--json` prints the same as
// one JSON object on stdout (nothing else goes to stdout), for scripts and tests:
//   file, file_bytes, format, format_details, elements (PLY), points, bounds {min, max},
//   quantization {scale, offset}, attributes (PointCloud::attributeNames order),
//   attribute_ranges {name: {min, max}}, load_seconds, mb_per_second, million_points_per_second.
// Non-finite numbers (the bounds of an empty cloud) are JSON null.
//
// A Potree 2.0 directory (or its metadata.json) is described without loading its points: the
// same keys, with format "potree", format_details from metadata.json plus the node count and
// depth of the whole hierarchy (every chunk is read, which also checks it), attribute_ranges
// as metadata.json declares them (x y z from the position's, the others under their Potree
// names in the file's units), and load_* for opening the directory and reading its hierarchy.
#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "command_info_copc.h"
#include "commands.h"
#include "core/byte_source_opener.h"
#include "core/column_names.h"
#include "core/error.h"
#include "core/point_cloud.h"
#include "core/progress.h"
#include "info_json.h"
#include "io/format_description.h"
#include "io/point_file.h"
#include "lod/copc_reader.h"
#include "lod/octree_export.h"
#include "lod/octree_open.h"
#include "lod/potree_reader.h"
#include "octree_export.h"
#include "progress_options.h"

namespace parallax::cli {
namespace {

using Json = InfoJson;

// ---------------------------------------------------------------------------------------------
// Per-attribute ranges, computed in parallel over the columns.

struct Range {
  double min = std::numeric_limits<double>::infinity();
  double max = -std::numeric_limits<double>::infinity();
  bool empty() const { return min > max; }
};

struct NamedRange {
  std::string name;
  Range range;
};

// Min and max of `components` values per point, value(i, c) read as double. NaN values are
// skipped (the comparisons are false for them), so one NaN normal does not hide the others' range.
template <int kComponents, class ValueAt>
std::array<Range, kComponents> columnRanges(std::size_t count, ValueAt value_at) {
  using Ranges = std::array<Range, kComponents>;
  constexpr std::size_t kGrain = 1 << 16;
  return tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, count, kGrain), Ranges{},
      [&](const tbb::blocked_range<std::size_t>& block, Ranges ranges) {
        for (std::size_t i = block.begin(); i != block.end(); ++i) {
          for (int c = 0; c < kComponents; ++c) {
            const double v = value_at(i, c);
            if (v < ranges[c].min) ranges[c].min = v;
            if (v > ranges[c].max) ranges[c].max = v;
          }
        }
        return ranges;
      },
      [](Ranges a, const Ranges& b) {
        for (int c = 0; c < kComponents; ++c) {
          a[c].min = std::min(a[c].min, b[c].min);
          a[c].max = std::max(a[c].max, b[c].max);
        }
        return a;
      });
}

template <class T>
Range scalarRange(const T* values, std::size_t count) {
  return columnRanges<1>(count, [values](std::size_t i, int) { return double(values[i]); })[0];
}

Range scalarColumnRange(const ScalarColumn& column, std::size_t count) {
  switch (column.type) {
    case ScalarType::Int8:
      return scalarRange(column.as<std::int8_t>(), count);
    case ScalarType::UInt8:
      return scalarRange(column.as<std::uint8_t>(), count);
    case ScalarType::Int16:
      return scalarRange(column.as<std::int16_t>(), count);
    case ScalarType::UInt16:
      return scalarRange(column.as<std::uint16_t>(), count);
    case ScalarType::Int32:
      return scalarRange(column.as<std::int32_t>(), count);
    case ScalarType::UInt32:
      return scalarRange(column.as<std::uint32_t>(), count);
    case ScalarType::Float32:
      return scalarRange(column.as<float>(), count);
    case ScalarType::Float64:
      return scalarRange(column.as<double>(), count);
  }
  return {};
}

// Ranges in the order of PointCloud::attributeNames(). Positions are world coordinates: the
// range of the quantized integers mapped through the quantization (exact, like `bounds`).
std::vector<NamedRange> attributeRanges(const PointCloud& cloud) {
  std::vector<NamedRange> out;
  const std::size_t n = cloud.count;
  const char* const kAxes[3] = {column_names::kX, column_names::kY, column_names::kZ};
  if (!cloud.positions.empty()) {
    const Int3* p = cloud.positions.data();
    auto q = columnRanges<3>(n, [p](std::size_t i, int c) {
      return double(c == 0 ? p[i].x : c == 1 ? p[i].y : p[i].z);
    });
    for (int c = 0; c < 3; ++c) {
      Range world;
      if (!q[c].empty()) {
        const double a = cloud.quantization.toWorld(c, std::int32_t(q[c].min));
        const double b = cloud.quantization.toWorld(c, std::int32_t(q[c].max));
        world = {std::min(a, b), std::max(a, b)};  // a negative scale swaps the ends
      }
      out.push_back({kAxes[c], world});
    }
  } else {
    for (const char* axis : kAxes) out.push_back({axis, Range{}});
  }
  if (cloud.hasColors()) {
    const Rgba8* rgba = cloud.colors.data();
    auto r = columnRanges<4>(n, [rgba](std::size_t i, int c) {
      return double(c == 0 ? rgba[i].r : c == 1 ? rgba[i].g : c == 2 ? rgba[i].b : rgba[i].a);
    });
    out.push_back({column_names::kRed, r[0]});
    out.push_back({column_names::kGreen, r[1]});
    out.push_back({column_names::kBlue, r[2]});
    if (cloud.source.has_alpha) out.push_back({column_names::kAlpha, r[3]});
  }
  if (cloud.hasNormals()) {
    const Float3* nrm = cloud.normals.data();
    auto r = columnRanges<3>(n, [nrm](std::size_t i, int c) {
      return double(c == 0 ? nrm[i].x : c == 1 ? nrm[i].y : nrm[i].z);
    });
    out.push_back({column_names::kNx, r[0]});
    out.push_back({column_names::kNy, r[1]});
    out.push_back({column_names::kNz, r[2]});
  }
  if (cloud.hasIntensity())
    out.push_back({column_names::kIntensity, scalarRange(cloud.intensity.data(), n)});
  if (cloud.hasClassification()) {
    out.push_back({column_names::kClassification, scalarRange(cloud.classification.data(), n)});
  }
  for (const auto& column : cloud.scalars) {
    out.push_back({column.name, scalarColumnRange(column, n)});
  }
  return out;
}

// ---------------------------------------------------------------------------------------------
// The format's own description: its row's (io/point_format.h). Formats without one (text) show
// their name and what was loaded.

FormatDescription describeFormat(const std::filesystem::path& path, PointFormat format) {
  const PointFormatEntry* row = format.entry();
  if (row != nullptr && row->describe) return row->describe(path);
  FormatDescription out;
  out.name = row != nullptr ? row->id : "unknown";
  out.summary = pointFormatName(format);
  return out;
}

// ---------------------------------------------------------------------------------------------
// Output.

struct LoadStats {
  std::uint64_t file_bytes = 0;
  double seconds = 0;
  double megabytesPerSecond() const { return seconds > 0 ? file_bytes / seconds / 1e6 : 0; }
  double millionPointsPerSecond(std::uint64_t points) const {
    return seconds > 0 ? points / seconds / 1e6 : 0;
  }
};

void printJson(const std::filesystem::path& path, const FormatDescription& format,
               const PointCloud& cloud, const std::vector<NamedRange>& ranges,
               const LoadStats& load) {
  Json ranges_json = Json::object();
  for (const auto& [name, range] : ranges) {
    ranges_json[name] = {{"min", finiteOrNull(range.min)}, {"max", finiteOrNull(range.max)}};
  }
  Json out = {
      {"file", path.string()},
      {"file_bytes", load.file_bytes},
      {"format", format.name},
      {"format_details", format.details},
      {"elements", format.elements},
      {"points", cloud.count},
      {"bounds", {{"min", jsonTriple(cloud.bounds.min)}, {"max", jsonTriple(cloud.bounds.max)}}},
      {"quantization",
       {{"scale", jsonTriple(cloud.quantization.scale)},
        {"offset", jsonTriple(cloud.quantization.offset)}}},
      {"attributes", cloud.attributeNames()},
      {"attribute_ranges", ranges_json},
      {"load_seconds", load.seconds},
      {"mb_per_second", load.megabytesPerSecond()},
      {"million_points_per_second", load.millionPointsPerSecond(cloud.count)},
  };
  if (format.declared_bounds) {
    out["declared_bounds"] = {{"min", jsonTriple(format.declared_bounds->min)},
                              {"max", jsonTriple(format.declared_bounds->max)}};
  }
  std::puts(out.dump(2).c_str());
}

std::string formatTriple(const std::array<double, 3>& v) {
  char text[128];
  std::snprintf(text, sizeof text, "(%.10g, %.10g, %.10g)", v[0], v[1], v[2]);
  return text;
}

void printText(const std::filesystem::path& path, const FormatDescription& format,
               const PointCloud& cloud, const std::vector<NamedRange>& ranges,
               const LoadStats& load) {
  std::printf("file          %s (%llu bytes, %.1f MB)\n", path.c_str(),
              static_cast<unsigned long long>(load.file_bytes), load.file_bytes / 1e6);
  std::printf("format        %s\n",
              format.summary.empty() ? format.name.c_str() : format.summary.c_str());
  for (const auto& line : format.lines) std::printf("%s\n", line.c_str());
  std::printf("points        %llu\n", static_cast<unsigned long long>(cloud.count));
  if (cloud.bounds.empty()) {
    std::printf("bounds        none (no points)\n");
  } else {
    std::printf("bounds        min %s\n", formatTriple(cloud.bounds.min).c_str());
    std::printf("              max %s\n", formatTriple(cloud.bounds.max).c_str());
    std::printf("              size %s\n", formatTriple(cloud.bounds.size()).c_str());
  }
  if (format.declared_bounds) {
    std::printf("file bounds   min %s\n", formatTriple(format.declared_bounds->min).c_str());
    std::printf("              max %s\n", formatTriple(format.declared_bounds->max).c_str());
  }
  std::printf("quantization  scale %s offset %s\n", formatTriple(cloud.quantization.scale).c_str(),
              formatTriple(cloud.quantization.offset).c_str());
  std::printf("attributes   ");
  for (const auto& name : cloud.attributeNames()) std::printf(" %s", name.c_str());
  std::printf("\nranges\n");
  std::size_t width = 4;
  for (const auto& entry : ranges) width = std::max(width, entry.name.size());
  for (const auto& [name, range] : ranges) {
    if (range.empty()) {
      std::printf("  %-*s  none\n", int(width), name.c_str());
    } else {
      std::printf("  %-*s  %16.10g  %16.10g\n", int(width), name.c_str(), range.min, range.max);
    }
  }
  std::printf("load          %.3f s (%.1f MB/s, %.2f M points/s)\n", load.seconds,
              load.megabytesPerSecond(), load.millionPointsPerSecond(cloud.count));
}

// ---------------------------------------------------------------------------------------------
// Potree 2.0 directories.

Json potreeRange(const std::vector<double>& values) {
  if (values.empty()) return nullptr;
  if (values.size() == 1) return finiteOrNull(values[0]);
  Json out = Json::array();
  for (double v : values) out.push_back(finiteOrNull(v));
  return out;
}

// One line for metadata.json's "projection": a WKT's name ("NAD83 / UTM zone 15N (WKT)"), a
// proj4 string or EPSG code as it is, "none" when empty.
std::string describeProjection(const std::string& projection) {
  if (projection.empty()) return "none";
  const auto bracket = projection.find('[');
  const auto quote = projection.find('"');
  if (bracket != std::string::npos && quote != std::string::npos && bracket < quote) {
    const auto end = projection.find('"', quote + 1);
    if (end != std::string::npos) return projection.substr(quote + 1, end - quote - 1) + " (WKT)";
  }
  return projection;
}

int runPotreeInfo(const std::filesystem::path& path, bool json) {
  const auto start = std::chrono::steady_clock::now();
  std::unique_ptr<Octree> octree = openPotree(path);
  // Every chunk, so that the node count and depth are the whole tree's (expanding appends).
  expandWholeHierarchy(*octree);
  LoadStats load;
  load.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const PotreeMetadata& metadata = *potreeMetadata(*octree);
  const OctreeInfo& info = octree->info();
  load.file_bytes = potreeReadStats(*octree)->file_bytes;
  int depth = 0;
  for (const auto& node : octree->nodes()) depth = std::max(depth, node.level);
  const std::size_t node_count = octree->nodes().size();

  Json attributes = Json::array();
  Json ranges = Json::object();
  const char* const kAxes[3] = {column_names::kX, column_names::kY, column_names::kZ};
  for (int axis = 0; axis < 3; ++axis) {
    ranges[kAxes[axis]] = {{"min", finiteOrNull(info.bounds.min[axis])},
                           {"max", finiteOrNull(info.bounds.max[axis])}};
  }
  for (const auto& a : metadata.attributes) {
    attributes.push_back({{"name", a.name},
                          {"type", std::string(potreeTypeName(a.type))},
                          {"elements", a.num_elements}});
    if (a.name != "position")
      ranges[a.name] = {{"min", potreeRange(a.min)}, {"max", potreeRange(a.max)}};
  }
  Json details = {
      {"version", metadata.version},
      {"encoding", metadata.encoding},
      {"record_bytes", metadata.record_size},
      {"nodes", node_count},
      {"depth", depth},
      {"declared_depth", metadata.hierarchy.depth},
      {"spacing", metadata.spacing},
      {"projection", metadata.projection},
      {"cube", {{"min", jsonTriple(info.cube.min)}, {"max", jsonTriple(info.cube.max)}}},
      {"potree_attributes", attributes}};
  if (json) {
    Json out = {
        {"file", path.string()},
        {"file_bytes", load.file_bytes},
        {"format", "potree"},
        {"format_details", details},
        {"elements", nullptr},
        {"points", info.point_count},
        {"bounds", {{"min", jsonTriple(info.bounds.min)}, {"max", jsonTriple(info.bounds.max)}}},
        {"quantization",
         {{"scale", jsonTriple(info.quantization.scale)},
          {"offset", jsonTriple(info.quantization.offset)}}},
        {"attributes", info.attributes},
        {"attribute_ranges", ranges},
        {"load_seconds", load.seconds},
        {"mb_per_second", load.megabytesPerSecond()},
        {"million_points_per_second", load.millionPointsPerSecond(info.point_count)},
    };
    std::puts(out.dump(2).c_str());
    return 0;
  }
  std::printf("file          %s (%llu bytes, %.1f MB)\n", path.c_str(),
              static_cast<unsigned long long>(load.file_bytes), load.file_bytes / 1e6);
  std::printf("format        Potree %s, %s encoding, %zu-byte records\n", metadata.version.c_str(),
              metadata.encoding.c_str(), metadata.record_size);
  std::printf("  nodes %zu (depth %d; metadata says %d), root spacing %.10g\n", node_count, depth,
              metadata.hierarchy.depth, metadata.spacing);
  for (const auto& a : metadata.attributes) {
    std::printf("  attribute %s %s x %d\n", a.name.c_str(),
                std::string(potreeTypeName(a.type)).c_str(), a.num_elements);
  }
  std::printf("points        %llu\n", static_cast<unsigned long long>(info.point_count));
  std::printf("bounds        min %s\n", formatTriple(info.bounds.min).c_str());
  std::printf("              max %s\n", formatTriple(info.bounds.max).c_str());
  std::printf("cube          min %s\n", formatTriple(info.cube.min).c_str());
  std::printf("              max %s\n", formatTriple(info.cube.max).c_str());
  std::printf("quantization  scale %s offset %s\n", formatTriple(info.quantization.scale).c_str(),
              formatTriple(info.quantization.offset).c_str());
  std::printf("projection    %s\n", describeProjection(metadata.projection).c_str());
  std::printf("attributes   ");
  for (const auto& name : info.attributes) std::printf(" %s", name.c_str());
  std::printf("\nopen          %.3f s (metadata and the whole hierarchy)\n", load.seconds);
  return 0;
}

struct InfoOptions {
  std::string file;
  bool json = false;
  bool quiet = false;    // no loading bar (the description is the command's result: printed)
  bool formats = false;  // the format table instead of a file
};

int runInfo(const InfoOptions& options) {
  if (options.formats) {
    // docs/FORMATS.md holds this table (a test compares them).
    std::fputs(pointFormatsMarkdown().c_str(), stdout);
    return 0;
  }
  if (options.file.empty()) {
    throw std::invalid_argument("info: no file (give a point file, or --formats)");
  }
  const std::filesystem::path path = options.file;
  // A URL of an octree or of any point file: the format table opens it by range (a LAS or LAZ
  // file's header and chunks) as it opens a path.
  if (isPotreeDirectory(path)) return runPotreeInfo(path, options.json);
  if (detectOctreeFormat(path) == OctreeFormat::Copc) return runCopcInfo(path, options.json);
  // Detection opens the file: a missing or unreadable file is an InputError naming it.
  const PointFormat format = detectPointFormat(path);

  LoadStats load;
  std::error_code size_error;
  load.file_bytes = isUrl(options.file) ? openByteSource(options.file)->size()
                                        : std::filesystem::file_size(path, size_error);
  if (size_error) load.file_bytes = 0;  // a pipe or special file: no rate in MB/s

  PointCloud cloud;
  {
    const auto progress = readingBar(options.quiet, "loading " + path.filename().string(), path);
    PointReadOptions read_options;
    read_options.progress = progress.get();
    const auto start = std::chrono::steady_clock::now();
    cloud = readPointFile(path, read_options);
    load.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  // After the load: readPointFile has already reported a malformed file with its own message.
  const FormatDescription description = describeFormat(path, format);
  const std::vector<NamedRange> ranges = attributeRanges(cloud);

  if (options.json) {
    printJson(path, description, cloud, ranges, load);
  } else {
    printText(path, description, cloud, ranges, load);
  }
  return 0;
}

}  // namespace

Command addInfoCommand(CLI::App& app) {
  auto options = std::make_shared<InfoOptions>();
  Command command;
  command.subcommand =
      app.add_subcommand("info",
                         "Describe a point file: format, points, bounds, attribute "
                         "ranges, load speed");
  command.subcommand->add_option("file", options->file,
                                 "Point file (" + pointFormatNamesText() +
                                     "; format detected from its content), Potree 2.0 directory "
                                     "or COPC file (or its http(s) URL)");
  command.subcommand->add_flag("--formats", options->formats,
                               "List the point formats this build reads and writes (Markdown)");
  command.subcommand->add_flag("--json", options->json,
                               "Print one JSON object (points, bounds, attributes, ...)");
  addQuietFlag(*command.subcommand, options->quiet);
  command.run = [options] { return runInfo(*options); };
  return command;
}

}  // namespace parallax::cli
