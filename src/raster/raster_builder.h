// `parallax raster`: a cloud streamed in chunks into a float32 GeoTIFF of one value per cell
// (cell_accumulator.h), out of core.
//
// Memory is the grid, never the points: the accumulator of a band of rows (bytesPerCell + 4 bytes
// of output a cell) is what --memory bounds. A grid that fits is one band and the cloud is read
// once; a larger one is cut into bands of whole tile rows (256 rows) and the cloud is read once
// per band, each band written to the GeoTIFF as it is finished. Reading again costs time, not
// memory, and keeps nothing on disk but the output (a spill of the points would cost their size
// on disk and a write of all of them; bands of a DTM under 2 GB are rare).
// --fill, --minus and the hillshade work on the whole raster, so they need it to fit --memory.
//
// The grid covers the whole cloud (the header's bounds for LAS, LAZ and COPC; a first pass over
// the points otherwise), filters or not, so that the rasters of one cloud (DTM, DSM) line up.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "core/point_filter.h"
#include "io/coordinate_system.h"
#include "raster/cell_accumulator.h"
#include "raster/raster_image.h"

namespace parallax {

// A cloud to read: any point file the format table opens, with the points to use.
struct RasterInput {
  std::filesystem::path path;
  std::vector<std::string> text_columns;  // text files (see io/point_file.h)
  PointFilter filter;                     // --classes, --returns, ...
  // The grid positions are put on, when a first pass found it (text files: then read once less
  // per pass); absent: the reader's own choice.
  std::optional<Quantization> quantization;
};

struct RasterOptions {
  RasterInput input;
  std::filesystem::path output;  // the GeoTIFF
  double resolution = 1.0;       // cell size, in the cloud's horizontal unit
  RasterValue value = RasterValue::Min;
  // --bounds XMIN,YMIN,XMAX,YMAX: the grid's extent (raster_grid.h boundedGrid); absent: the
  // cloud's, aligned to multiples of the resolution.
  std::optional<std::array<double, 4>> bounds;
  double idw_radius = 0.0;      // idw: the search radius; 0 = the resolution
  bool fill = false;            // fill gaps (raster_fill.h)
  double fill_radius = 0.0;     // 0 = 10 cells
  std::filesystem::path minus;  // subtract this raster (same grid): a CHM from a DSM and a DTM
  bool hillshade = false;       // OUT_hillshade.png beside the output
  std::uint64_t memory_mb = 2048;
};

struct RasterReport {
  RasterGrid grid;
  std::uint64_t points_read = 0;  // after the filter
  std::uint64_t points_used = 0;  // in the grid's cells
  std::uint64_t bands = 0;        // reads of the cloud for the cells
  std::uint64_t cells_with_value = 0;
  std::uint64_t cells_filled = 0;
  std::string crs;  // summary, "none"
  std::filesystem::path hillshade;
};

// Throws std::invalid_argument naming the option for a bad option, InputError for a bad input
// file, std::runtime_error for an output that cannot be written.
RasterReport buildRaster(const RasterOptions& options);

// The path of the hillshade beside `output`: "dtm.tif" -> "dtm_hillshade.png".
std::filesystem::path hillshadePathFor(const std::filesystem::path& output);

// What the cloud covers in x and y (header bounds where the file states them, else a pass over
// its points) and its CRS: what the grid is planned from.
struct CloudExtent {
  double min_x = 0, min_y = 0, max_x = 0, max_y = 0;
  bool empty = true;
  CoordinateSystem crs;
  std::optional<Quantization> quantization;  // found by the pass over the points, if one ran
};
CloudExtent cloudExtent(const RasterInput& input);

// Streams the cloud once and returns rows [first_row, last_row) of `value` on `grid` (row-major,
// `nodata` in empty cells); adds to the counts of `report` (points read and used).
std::vector<float> rasterizeRows(const RasterInput& input, const RasterGrid& grid,
                                 RasterValue value, double idw_radius, std::int64_t first_row,
                                 std::int64_t last_row, float nodata, RasterReport& report);

}  // namespace parallax
