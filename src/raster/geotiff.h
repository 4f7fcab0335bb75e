// GeoTIFF through GDAL: the float32 rasters Parallax writes (one band, tiled 256 x 256, DEFLATE,
// nodata and CRS set, the exact geotransform of the grid) and the ones it reads back (--minus,
// volume's --base FILE.tif). Outputs are written under a temporary name beside the target
// (io/partial_output.h) and renamed when complete.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "io/coordinate_system.h"
#include "raster/raster_image.h"

namespace parallax {

// The CRS of a cloud as OGC WKT for GDAL: the LAS WKT record as written, else the EPSG code of
// the GeoTIFF keys (projected, else geographic) through GDAL's database; empty without a CRS. A
// vertical datum is left out (GeoTIFF keys of a compound CRS are a later step).
std::string wktOfCoordinateSystem(const CoordinateSystem& crs);

// Whether two CRSs given as WKT (a cloud's, wktOfCoordinateSystem; a raster's, readRaster) are
// the same one, as GDAL's OSRIsSame judges (names and axis order aside, the datum, projection
// and parameters compared); equal strings are. False where GDAL cannot read one of them.
bool sameCoordinateSystem(const std::string& wkt_a, const std::string& wkt_b);
// A CRS's name for a message: "WGS 84 / UTM zone 33N (EPSG:32633)", the name alone without an
// authority code; the WKT's first 60 characters where GDAL cannot read it; "none" for "".
std::string coordinateSystemName(const std::string& wkt);

// Writes a GeoTIFF band by band (rows from the top) under a temporary name; commit() renames it.
// Destroyed uncommitted, the temporary file is removed. Errors are std::runtime_error naming the
// output path and GDAL's message.
class GeoTiffWriter {
 public:
  GeoTiffWriter(const std::filesystem::path& path, const RasterGrid& grid, const std::string& wkt,
                float nodata);
  ~GeoTiffWriter();
  GeoTiffWriter(const GeoTiffWriter&) = delete;
  GeoTiffWriter& operator=(const GeoTiffWriter&) = delete;

  // Rows [first_row, first_row + values.size() / columns) of the band.
  void writeRows(std::int64_t first_row, const std::vector<float>& values);
  void commit();

  struct Dataset;  // GDAL's handle (geotiff.cpp)

 private:
  std::filesystem::path path_;
  std::filesystem::path temp_;
  RasterGrid grid_;
  std::unique_ptr<Dataset> dataset_;
  bool committed_ = false;
};

void writeGeoTiff(const RasterImage& image, const std::filesystem::path& path);

// GDAL's block cache is process-wide and by default 5 % of the machine's memory, on top of any
// budget: the tiles written through GeoTiffWriter wait there. Lowers its limit to `bytes` (never
// raises it); gdalCacheLimit is the limit in effect.
void limitGdalCache(std::uint64_t bytes);
std::uint64_t gdalCacheLimit();

// Band 1 of any raster GDAL reads, as float32, with its geotransform (north-up, square cells),
// nodata (kRasterNodata where the file states none) and WKT. Throws InputError naming the file
// for a file GDAL cannot open, a rotated or non-square grid.
RasterImage readRaster(const std::filesystem::path& path);

// Writes 8-bit grey pixels (rows from the top) as a PNG through GDAL, temporary name and rename.
void writeGreyPng(const std::filesystem::path& path, std::int64_t columns, std::int64_t rows,
                  const std::vector<std::uint8_t>& pixels);

}  // namespace parallax
