#include "raster/raster_builder.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "io/partial_output.h"
#include "io/point_file.h"
#include "lod/convert_stages.h"
#include "raster/geotiff.h"
#include "raster/hillshade.h"
#include "raster/raster_fill.h"

namespace parallax {

namespace {

// Points a chunk: large enough to amortise the reader's calls, small beside any grid.
constexpr std::size_t kChunkPoints = 1 << 20;
// Bands are whole rows of the GeoTIFF's 256 x 256 tiles, so each tile is written once.
constexpr std::int64_t kTileRows = 256;

void checkOptions(const RasterOptions& options) {
  if (!(options.resolution > 0.0) || !std::isfinite(options.resolution)) {
    throw std::invalid_argument("--resolution: expected a positive number of units a cell, found " +
                                std::to_string(options.resolution));
  }
  if (options.idw_radius < 0.0 || !std::isfinite(options.idw_radius)) {
    throw std::invalid_argument("--idw-radius: expected a positive distance, found " +
                                std::to_string(options.idw_radius));
  }
  if (options.fill_radius < 0.0 || !std::isfinite(options.fill_radius)) {
    throw std::invalid_argument("--fill-radius: expected a positive distance, found " +
                                std::to_string(options.fill_radius));
  }
  if (options.bounds) {
    const auto& b = *options.bounds;
    if (!std::all_of(b.begin(), b.end(), [](double v) { return std::isfinite(v); }) ||
        b[0] >= b[2] || b[1] >= b[3]) {
      throw std::invalid_argument(
          "--bounds: expected XMIN,YMIN,XMAX,YMAX with XMIN < XMAX and YMIN < YMAX");
    }
  }
  if (options.output.empty()) throw std::invalid_argument("-o: an output file is needed");
  // The cloud is read before the GeoTIFF replaces the output, so naming the input as the output
  // ran and replaced the point file with a GeoTIFF.
  requireOutputIsNotInput(options.output, options.input.path, "-o", "GeoTIFF");
  requireOutputFolder(options.output, "-o");
  const std::filesystem::path folder =
      options.output.has_parent_path() ? options.output.parent_path() : ".";
  if (::access(folder.c_str(), W_OK) != 0) {
    throw std::invalid_argument("-o " + options.output.string() + ": the folder " +
                                folder.string() + " is not writable");
  }
}

}  // namespace

std::filesystem::path hillshadePathFor(const std::filesystem::path& output) {
  std::filesystem::path path = output;
  path.replace_filename(output.stem().string() + "_hillshade.png");
  return path;
}

CloudExtent cloudExtent(const RasterInput& input) {
  CloudExtent extent;
  const PointFileHeader header = readPointFileHeader(input.path);
  extent.crs = header.crs;
  if (header.bounds && !header.bounds->empty()) {
    extent.min_x = header.bounds->min[0], extent.max_x = header.bounds->max[0];
    extent.min_y = header.bounds->min[1], extent.max_y = header.bounds->max[1];
    extent.empty = header.point_count && *header.point_count == 0;
    return extent;
  }
  PointStream stream(input.path, input.text_columns);
  extent.quantization = stream.quantization();
  PointCloud chunk;
  Bounds3 bounds;
  while (stream.next(chunk, kChunkPoints)) {
    for (std::size_t i = 0; i < chunk.count; ++i) {
      bounds.extend(chunk.worldX(i), chunk.worldY(i), chunk.worldZ(i));
    }
  }
  if (!bounds.empty()) {
    extent.min_x = bounds.min[0], extent.max_x = bounds.max[0];
    extent.min_y = bounds.min[1], extent.max_y = bounds.max[1];
    extent.empty = false;
  }
  return extent;
}

std::vector<float> rasterizeRows(const RasterInput& input, const RasterGrid& grid,
                                 RasterValue value, double idw_radius, std::int64_t first_row,
                                 std::int64_t last_row, float nodata, RasterReport& report) {
  CellAccumulator cells(grid, value, first_row, last_row, idw_radius);
  PointStream stream(input.path, input.text_columns,
                     input.quantization ? &*input.quantization : nullptr, &input.filter);
  PointCloud chunk;
  while (stream.next(chunk, kChunkPoints)) {
    cells.addChunk(chunk);
    report.points_read += chunk.count;
  }
  report.points_used += cells.pointsUsed();
  return cells.values(nodata);
}

RasterReport buildRaster(const RasterOptions& options) {
  checkOptions(options);
  RasterReport report;
  const CloudExtent extent = cloudExtent(options.input);
  report.crs = extent.crs.summary();
  RasterInput input = options.input;
  if (!input.quantization) input.quantization = extent.quantization;
  if (options.bounds) {
    const auto& b = *options.bounds;
    report.grid = boundedGrid(b[0], b[1], b[2], b[3], options.resolution);
  } else {
    if (extent.empty) {
      throw std::invalid_argument(options.input.path.string() +
                                  ": the cloud has no points to make a raster of (give --bounds "
                                  "for an empty raster)");
    }
    report.grid =
        alignedGrid(extent.min_x, extent.min_y, extent.max_x, extent.max_y, options.resolution);
  }
  const RasterGrid& grid = report.grid;
  checkGeoTiffTiles(grid);
  const double idw_radius = options.idw_radius > 0.0 ? options.idw_radius : options.resolution;

  // The band plan: the accumulator and the band's output floats within --memory, less GDAL's
  // block cache (an eighth of the budget, at most 64 MB), where the written tiles wait: left at
  // its default (5 % of RAM) it took the peak 1 GB past the budget (B2.e57 at 1e-6, 2048 MB:
  // 3.0 GB resident; 2.1 GB with the cache at 64 MB, the same bytes). Bands are whole tile rows,
  // so the tiles a small cache flushes are finished.
  const std::uint64_t cache =
      std::min<std::uint64_t>(std::uint64_t(64) << 20, (options.memory_mb << 20) / 8);
  limitGdalCache(cache);
  const std::uint64_t budget = (options.memory_mb << 20) - cache;
  const std::uint64_t row_bytes =
      std::uint64_t(grid.columns) * (CellAccumulator::bytesPerCell(options.value) + 4);
  std::int64_t band_rows = std::int64_t(std::max<std::uint64_t>(1, budget / row_bytes));
  const bool whole = options.fill || options.hillshade || !options.minus.empty();
  if (band_rows < grid.rows) {
    if (whole) {
      throw std::invalid_argument(
          "--memory: the grid of " + std::to_string(grid.columns) + " x " +
          std::to_string(grid.rows) + " cells needs " +
          std::to_string((row_bytes * std::uint64_t(grid.rows)) >> 20) +
          " MB held whole for --fill, --minus or --hillshade; raise --memory or --resolution");
    }
    if (band_rows >= kTileRows) band_rows -= band_rows % kTileRows;
  } else {
    band_rows = grid.rows;
  }

  const std::string wkt = wktOfCoordinateSystem(extent.crs);
  const float nodata = kRasterNodata;
  if (!whole) {
    GeoTiffWriter writer(options.output, grid, wkt, nodata);
    for (std::int64_t first = 0; first < grid.rows; first += band_rows) {
      const std::int64_t last = std::min(grid.rows, first + band_rows);
      const std::vector<float> values =
          rasterizeRows(input, grid, options.value, idw_radius, first, last, nodata, report);
      for (float v : values) report.cells_with_value += v != nodata;
      writer.writeRows(first, values);
      ++report.bands;
    }
    writer.commit();
    return report;
  }

  RasterImage image;
  image.grid = grid;
  image.wkt = wkt;
  image.nodata = nodata;
  image.values =
      rasterizeRows(input, grid, options.value, idw_radius, 0, grid.rows, nodata, report);
  report.bands = 1;
  if (options.fill) {
    const double radius =
        options.fill_radius > 0.0 ? options.fill_radius : kDefaultFillCells * options.resolution;
    report.cells_filled = fillNodata(image, radius);
  }
  if (!options.minus.empty()) {
    const RasterImage other = readRaster(options.minus);
    if (!sameGrid(other.grid, grid)) {
      throw std::invalid_argument(
          "--minus " + options.minus.string() + ": its grid (" +
          std::to_string(other.grid.columns) + " x " + std::to_string(other.grid.rows) +
          " cells of " + std::to_string(other.grid.resolution) + " from " +
          std::to_string(other.grid.left) + ", " + std::to_string(other.grid.top) +
          ") is not this raster's (" + std::to_string(grid.columns) + " x " +
          std::to_string(grid.rows) + " of " + std::to_string(grid.resolution) + " from " +
          std::to_string(grid.left) + ", " + std::to_string(grid.top) +
          "): make both from the same cloud and --resolution");
    }
    for (std::size_t i = 0; i < image.values.size(); ++i) {
      if (image.values[i] == nodata) continue;
      image.values[i] =
          other.values[i] == other.nodata ? nodata : image.values[i] - other.values[i];
    }
  }
  for (float v : image.values) report.cells_with_value += v != nodata;
  writeGeoTiff(image, options.output);
  if (options.hillshade) {
    report.hillshade = hillshadePathFor(options.output);
    writeGreyPng(report.hillshade, grid.columns, grid.rows, hillshade(image));
  }
  return report;
}

}  // namespace parallax
