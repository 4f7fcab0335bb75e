#include "lod/copc_converter.h"

#include <algorithm>
#include <chrono>
#include <cstring>

#include "io/las_header.h"
#include "io/point_file.h"
#include "lod/potree_reader.h"

namespace parallax {
namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

}  // namespace

CarriedCrs crsOfInputs(const std::vector<ConvertInput>& inputs) {
  CarriedCrs carried;
  std::string wkt_of;  // the input whose WKT is carried
  for (const ConvertInput& input : inputs) {
    const PointFormat format = detectPointFormat(input.path);
    if (format != PointFormat::Las && format != PointFormat::Laz) continue;
    const LasHeader header = readLasHeader(input.path);
    if (!carried.gps_time_standard) carried.gps_time_standard = header.gpsTimeIsStandard();
    if (header.crs.empty()) continue;
    if (header.crs.wkt.empty()) {
      std::string note = "the CRS of ";
      note += input.path.string();
      note += " (";
      note += header.crs.summary();
      note += "): GeoTIFF keys, and COPC needs WKT";
      carried.notes.push_back(std::move(note));
      continue;
    }
    if (wkt_of.empty()) {
      for (const LasVlr& vlr : header.vlrs) {
        if (vlr.user_id == "LASF_Projection" && vlr.record_id == 2112 && !vlr.extended) {
          carried.vlrs.push_back(vlr);
        }
      }
      if (carried.vlrs.empty()) {  // the WKT was in an EVLR: a VLR of it
        LasVlr vlr{.user_id = "LASF_Projection", .record_id = 2112, .description = "WKT"};
        const std::string& text = header.crs.wkt;
        vlr.data.resize(text.size() + 1);
        std::memcpy(vlr.data.data(), text.data(), text.size());
        carried.vlrs.push_back(std::move(vlr));
      }
      wkt_of = input.path.string();
    } else if (header.crs.wkt !=
               std::string(reinterpret_cast<const char*>(carried.vlrs.front().data.data()))) {
      std::string note = "the CRS of ";
      note += input.path.string();
      note += " (";
      note += header.crs.summary();
      note += "): the output has the CRS of ";
      note += wkt_of;
      carried.notes.push_back(std::move(note));
    }
  }
  return carried;
}

std::uint64_t copcBatchPoints(std::uint64_t memory_bytes) {
  // A node's cloud (about 60 bytes a point with LAS's columns), its records (about 40) and its
  // chunk (about 15), with room to spare.
  constexpr std::uint64_t kBytesPerPoint = 160;
  return std::clamp<std::uint64_t>(memory_bytes / 4 / kBytesPerPoint, 1u << 16, 1u << 22);
}

CopcConvertResult convertToCopc(const std::vector<ConvertInput>& inputs,
                                const std::filesystem::path& output,
                                const CopcConvertOptions& options) {
  const auto start = Clock::now();
  CopcConvertResult result;
  CarriedCrs crs = crsOfInputs(inputs);
  result.notes = std::move(crs.notes);

  std::filesystem::path target = std::filesystem::absolute(output).lexically_normal();
  std::filesystem::create_directories(target.parent_path());
  std::filesystem::path tree_path = partialPathFor(target);
  tree_path += ".octree";
  const TemporaryDirectory tree(tree_path);
  PotreeConvertOptions build = options.potree;
  build.name = target.filename().string();
  result.build = convertToPotree(inputs, tree.path(), build);

  const auto mark = Clock::now();
  std::unique_ptr<Octree> octree = openPotree(tree.path());
  std::unique_ptr<Progress> progress;
  if (options.potree.progress)
    progress = options.potree.progress("writing COPC", result.build.points);
  CopcWriteOptions write;
  write.vlrs = std::move(crs.vlrs);
  write.gps_time_standard = crs.gps_time_standard;
  write.page_levels = options.page_levels;
  write.batch_points = copcBatchPoints(options.potree.build.memory_bytes);
  write.progress = progress.get();
  write.cancel = options.potree.build.cancel;
  result.copc = writeCopc(*octree, target, write);
  result.seconds_write = secondsSince(mark);
  result.seconds_total = secondsSince(start);
  return result;
}

}  // namespace parallax
