#include "raster/geotiff.h"

#include <cpl_conv.h>
#include <cpl_error.h>
#include <cpl_string.h>
#include <gdal.h>
#include <ogr_srs_api.h>

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <mutex>
#include <stdexcept>
#include <system_error>

#include "core/error.h"
#include "io/partial_output.h"

namespace parallax {

namespace {

void registerGdal() {
  static std::once_flag once;
  std::call_once(once, [] { GDALAllRegister(); });
}

// GDAL reports through a global error handler (stderr by default); Parallax reports errors
// itself, with the path, so GDAL's are kept quiet and read back with CPLGetLastErrorMsg.
class QuietGdalErrors {
 public:
  QuietGdalErrors() {
    CPLPushErrorHandler(CPLQuietErrorHandler);
    CPLErrorReset();
  }
  ~QuietGdalErrors() { CPLPopErrorHandler(); }
  QuietGdalErrors(const QuietGdalErrors&) = delete;
  QuietGdalErrors& operator=(const QuietGdalErrors&) = delete;

  static bool failed() { return CPLGetLastErrorType() >= CE_Failure; }
  static std::string message() {
    const char* text = CPLGetLastErrorMsg();
    return text && *text ? text : "no message from GDAL";
  }
};

[[noreturn]] void failWriting(const std::filesystem::path& path, const std::string& what) {
  throw std::runtime_error("cannot write " + path.string() + ": " + what);
}

GDALDriverH driverNamed(const char* name) {
  registerGdal();
  GDALDriverH driver = GDALGetDriverByName(name);
  if (!driver) {
    throw std::runtime_error(std::string("GDAL has no ") + name +
                             " driver (install the Debian package libgdal32)");
  }
  return driver;
}

void renameInto(const std::filesystem::path& temp, const std::filesystem::path& path) {
  std::error_code error;
  std::filesystem::rename(temp, path, error);
  if (error) {
    std::filesystem::remove(temp, error);
    failWriting(path, "renaming the finished file failed");
  }
}

std::string geoTransformText(const std::array<double, 6>& gt) {
  char text[256];
  std::snprintf(text, sizeof text, "[%.17g, %.17g, %.17g, %.17g, %.17g, %.17g]", gt[0], gt[1],
                gt[2], gt[3], gt[4], gt[5]);
  return text;
}

}  // namespace

namespace {

// A spatial reference read from WKT, or none (null) where GDAL cannot read it.
class SpatialReference {
 public:
  explicit SpatialReference(const std::string& wkt) : handle_(OSRNewSpatialReference(nullptr)) {
    // OSRSetFromUserInput takes WKT 1 and 2 alike (and "EPSG:n"); the pointer is not kept.
    if (OSRSetFromUserInput(handle_, wkt.c_str()) != OGRERR_NONE) {
      OSRDestroySpatialReference(handle_);
      handle_ = nullptr;
    }
  }
  ~SpatialReference() {
    if (handle_) OSRDestroySpatialReference(handle_);
  }
  SpatialReference(const SpatialReference&) = delete;
  SpatialReference& operator=(const SpatialReference&) = delete;
  OGRSpatialReferenceH get() const { return handle_; }

 private:
  OGRSpatialReferenceH handle_;
};

}  // namespace

bool sameCoordinateSystem(const std::string& wkt_a, const std::string& wkt_b) {
  if (wkt_a == wkt_b) return true;
  registerGdal();
  QuietGdalErrors quiet;
  const SpatialReference a(wkt_a), b(wkt_b);
  return a.get() && b.get() && OSRIsSame(a.get(), b.get()) != 0;
}

std::string coordinateSystemName(const std::string& wkt) {
  if (wkt.empty()) return "none";
  registerGdal();
  QuietGdalErrors quiet;
  const SpatialReference srs(wkt);
  const char* name = srs.get() ? OSRGetName(srs.get()) : nullptr;
  if (!name) return quoteInput(wkt, 60);
  std::string text = name;
  // The code of the CRS itself (the root node, nullptr), not of its datum or base.
  const char* authority = OSRGetAuthorityName(srs.get(), nullptr);
  const char* code = OSRGetAuthorityCode(srs.get(), nullptr);
  if (authority && code) text += std::string(" (") + authority + ":" + code + ")";
  return text;
}

struct GeoTiffWriter::Dataset {
  GDALDatasetH handle = nullptr;
};

std::string wktOfCoordinateSystem(const CoordinateSystem& crs) {
  if (!crs.description.wkt.empty()) return crs.description.wkt;
  const auto code = crs.description.projected_epsg ? crs.description.projected_epsg
                                                   : crs.description.geographic_epsg;
  if (!code || *code == 32767) return "";  // none, or user-defined (no code to look up)
  registerGdal();
  QuietGdalErrors quiet;
  OGRSpatialReferenceH srs = OSRNewSpatialReference(nullptr);
  std::string wkt;
  if (OSRImportFromEPSG(srs, *code) == OGRERR_NONE) {
    char* text = nullptr;
    if (OSRExportToWkt(srs, &text) == OGRERR_NONE && text) wkt = text;
    CPLFree(text);
  }
  OSRDestroySpatialReference(srs);
  return wkt;
}

GeoTiffWriter::GeoTiffWriter(const std::filesystem::path& path, const RasterGrid& grid,
                             const std::string& wkt, float nodata)
    : path_(path), temp_(newPartialFilePath(path)), grid_(grid), dataset_(new Dataset) {
  assert(grid.columns > 0 && grid.rows > 0 && "GeoTiffWriter: an empty grid");
  if (grid.columns > std::numeric_limits<int>::max() ||
      grid.rows > std::numeric_limits<int>::max()) {
    failWriting(path, "the grid of " + std::to_string(grid.columns) + " x " +
                          std::to_string(grid.rows) + " cells is beyond GDAL's 2^31 - 1 a side");
  }
  GDALDriverH driver = driverNamed("GTiff");
  QuietGdalErrors quiet;
  // Tiles of 256 x 256 compressed with DEFLATE: what GIS software reads fastest and a DEM of
  // real terrain shrinks well with; BIGTIFF only when the file may pass 4 GB.
  char** options = nullptr;
  options = CSLSetNameValue(options, "TILED", "YES");
  options = CSLSetNameValue(options, "BLOCKXSIZE", "256");
  options = CSLSetNameValue(options, "BLOCKYSIZE", "256");
  options = CSLSetNameValue(options, "COMPRESS", "DEFLATE");
  options = CSLSetNameValue(options, "BIGTIFF", "IF_SAFER");
  dataset_->handle =
      GDALCreate(driver, temp_.c_str(), int(grid.columns), int(grid.rows), 1, GDT_Float32, options);
  CSLDestroy(options);
  if (!dataset_->handle) failWriting(path, quiet.message());
  std::array<double, 6> transform = grid.geoTransform();
  if (GDALSetGeoTransform(dataset_->handle, transform.data()) != CE_None ||
      (!wkt.empty() && GDALSetProjection(dataset_->handle, wkt.c_str()) != CE_None) ||
      GDALSetRasterNoDataValue(GDALGetRasterBand(dataset_->handle, 1), nodata) != CE_None) {
    const std::string message = quiet.message();
    GDALClose(dataset_->handle);
    dataset_->handle = nullptr;
    std::error_code ignored;
    std::filesystem::remove(temp_, ignored);
    failWriting(path, message);
  }
}

GeoTiffWriter::~GeoTiffWriter() {
  if (committed_) return;
  if (dataset_->handle) {
    QuietGdalErrors quiet;
    GDALClose(dataset_->handle);
  }
  std::error_code ignored;
  std::filesystem::remove(temp_, ignored);
}

void GeoTiffWriter::writeRows(std::int64_t first_row, const std::vector<float>& values) {
  assert(values.size() % std::size_t(grid_.columns) == 0 &&
         "GeoTiffWriter::writeRows: whole rows only");
  const auto rows = std::int64_t(values.size() / std::size_t(grid_.columns));
  assert(first_row >= 0 && first_row + rows <= grid_.rows && "GeoTiffWriter: rows outside");
  QuietGdalErrors quiet;
  if (GDALRasterIO(GDALGetRasterBand(dataset_->handle, 1), GF_Write, 0, int(first_row),
                   int(grid_.columns), int(rows), const_cast<float*>(values.data()),
                   int(grid_.columns), int(rows), GDT_Float32, 0, 0) != CE_None) {
    failWriting(path_, quiet.message());
  }
}

void GeoTiffWriter::commit() {
  assert(!committed_ && "GeoTiffWriter::commit: already committed");
  {
    QuietGdalErrors quiet;
    GDALClose(dataset_->handle);  // flushes the last tiles: failures show as the last error
    dataset_->handle = nullptr;
    if (quiet.failed()) failWriting(path_, quiet.message());
  }
  renameInto(temp_, path_);
  committed_ = true;
}

void limitGdalCache(std::uint64_t bytes) {
  const auto limit = static_cast<GIntBig>(std::min<std::uint64_t>(bytes, INT64_MAX));
  if (GDALGetCacheMax64() > limit) GDALSetCacheMax64(limit);
}

std::uint64_t gdalCacheLimit() {
  return std::uint64_t(GDALGetCacheMax64());
}

void writeGeoTiff(const RasterImage& image, const std::filesystem::path& path) {
  GeoTiffWriter writer(path, image.grid, image.wkt, image.nodata);
  writer.writeRows(0, image.values);
  writer.commit();
}

RasterImage readRaster(const std::filesystem::path& path) {
  registerGdal();
  QuietGdalErrors quiet;
  GDALDatasetH dataset = GDALOpen(path.c_str(), GA_ReadOnly);
  auto fail = [&](const std::string& expected, const std::string& found) {
    if (dataset) GDALClose(dataset);
    InputErrorInfo info;
    info.file = path.string();
    info.element = "raster";
    info.expected = expected;
    info.found = found;
    throw InputError(info);
  };
  if (!dataset) fail("a raster GDAL can read (GeoTIFF, ...)", quiet.message());
  std::array<double, 6> gt{};
  if (GDALGetGeoTransform(dataset, gt.data()) != CE_None) {
    fail("a geotransform", "none (a raster without georeferencing)");
  }
  if (gt[2] != 0.0 || gt[4] != 0.0 || gt[5] >= 0.0 ||
      std::abs(gt[1] + gt[5]) > 1e-9 * std::abs(gt[1])) {
    fail("a north-up grid of square cells (geotransform [x, R, 0, y, 0, -R])",
         geoTransformText(gt));
  }
  RasterImage image;
  image.grid.left = gt[0];
  image.grid.top = gt[3];
  image.grid.resolution = gt[1];
  image.grid.columns = GDALGetRasterXSize(dataset);
  image.grid.rows = GDALGetRasterYSize(dataset);
  GDALRasterBandH band = GDALGetRasterBand(dataset, 1);
  int has_nodata = 0;
  const double nodata = GDALGetRasterNoDataValue(band, &has_nodata);
  image.nodata = has_nodata ? float(nodata) : kRasterNodata;
  if (const char* wkt = GDALGetProjectionRef(dataset)) image.wkt = wkt;
  image.values.resize(image.grid.cellCount());
  if (GDALRasterIO(band, GF_Read, 0, 0, int(image.grid.columns), int(image.grid.rows),
                   image.values.data(), int(image.grid.columns), int(image.grid.rows), GDT_Float32,
                   0, 0) != CE_None) {
    fail("readable band 1", quiet.message());
  }
  // NaN cells (a nodata of NaN, or none stated) become the nodata value, which compares equal.
  for (float& v : image.values) {
    if (std::isnan(v)) v = image.nodata;
  }
  if (std::isnan(image.nodata)) {
    image.nodata = kRasterNodata;
    for (float& v : image.values) {
      if (std::isnan(v)) v = kRasterNodata;
    }
  }
  GDALClose(dataset);
  return image;
}

void writeGreyPng(const std::filesystem::path& path, std::int64_t columns, std::int64_t rows,
                  const std::vector<std::uint8_t>& pixels) {
  assert(pixels.size() == std::size_t(columns) * std::size_t(rows) &&
         "writeGreyPng: one byte a pixel");
  GDALDriverH memory_driver = driverNamed("MEM");
  GDALDriverH png_driver = driverNamed("PNG");
  QuietGdalErrors quiet;
  // The PNG driver only copies a finished dataset: the pixels go to a MEM one first.
  GDALDatasetH memory =
      GDALCreate(memory_driver, "", int(columns), int(rows), 1, GDT_Byte, nullptr);
  if (!memory) failWriting(path, quiet.message());
  if (GDALRasterIO(GDALGetRasterBand(memory, 1), GF_Write, 0, 0, int(columns), int(rows),
                   const_cast<std::uint8_t*>(pixels.data()), int(columns), int(rows), GDT_Byte, 0,
                   0) != CE_None) {
    GDALClose(memory);
    failWriting(path, quiet.message());
  }
  const std::filesystem::path temp = newPartialFilePath(path);
  GDALDatasetH png =
      GDALCreateCopy(png_driver, temp.c_str(), memory, FALSE, nullptr, nullptr, nullptr);
  GDALClose(memory);
  if (!png) {
    std::error_code ignored;
    std::filesystem::remove(temp, ignored);
    failWriting(path, quiet.message());
  }
  GDALClose(png);
  if (quiet.failed()) {
    std::error_code ignored;
    std::filesystem::remove(temp, ignored);
    failWriting(path, quiet.message());
  }
  renameInto(temp, path);
}

}  // namespace parallax
