// The built-in rows of the format table (point_format.h), one function a format, listed in
// detection order at the end of the file. A row ties the format's reader, preview, chunk source,
// description and writer to the table; the work is in their own files.
#include <algorithm>
#include <fstream>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/byte_source.h"
#include "core/byte_source_opener.h"
#include "core/column_names.h"
#include "core/scalar_type.h"
#include "io/e57/e57_format.h"
#include "io/format_description.h"
#include "io/las_header.h"
#include "io/las_reader.h"
#include "io/las_record_decoder.h"
#include "io/las_writer.h"
#include "io/laz_reader.h"
#include "io/laz_writer.h"
#include "io/mapped_file.h"
#include "io/pcd_header.h"
#include "io/pcd_reader.h"
#include "io/pcd_writer.h"
#include "io/ply_header.h"
#include "io/ply_preview.h"
#include "io/ply_property_map.h"
#include "io/ply_reader.h"
#include "io/ply_writer.h"
#include "io/point_file.h"
#include "io/point_format.h"
#include "io/pts_reader.h"
#include "io/ptx_reader.h"
#include "io/ptx_writer.h"
#include "io/text_reader.h"
#include "io/text_writer.h"

namespace parallax {
namespace {

using Json = nlohmann::ordered_json;

Json finiteOrNull(double v) {
  return std::isfinite(v) ? Json(v) : Json(nullptr);
}

Json triple(const std::array<double, 3>& v) {
  return Json::array({finiteOrNull(v[0]), finiteOrNull(v[1]), finiteOrNull(v[2])});
}

std::vector<std::byte> readPrefix(const std::filesystem::path& path, std::size_t max_bytes) {
  if (isUrl(path.string())) {
    const std::unique_ptr<ByteSource> source = openByteSource(path.string(), max_bytes);
    std::vector<std::byte> bytes(std::size_t(std::min<std::uint64_t>(source->size(), max_bytes)));
    source->read(0, bytes, {.element = "header"});
    return bytes;
  }
  std::ifstream in(path, std::ios::binary);
  std::vector<std::byte> bytes(max_bytes);
  in.read(reinterpret_cast<char*>(bytes.data()), std::streamsize(max_bytes));
  bytes.resize(std::size_t(in.gcount()));
  return bytes;
}

// ---------------------------------------------------------------------------------------------
// PLY

// The PLY signature: the line "ply", with the blanks some exporters leave after it ("ply ",
// "ply\t") and a CR before its LF. A first line "ply" followed by other words, above a "format"
// line, is a PLY file with a broken first line: taken as PLY so that the header parser says
// what is wrong with it (an unknown format would say nothing useful).
bool looksLikePly(std::span<const std::byte> bytes) {
  const std::string_view text(reinterpret_cast<const char*>(bytes.data()),
                              std::min<std::size_t>(bytes.size(), 256));
  if (!text.starts_with("ply")) return false;
  std::size_t i = 3;
  while (i < text.size() && (text[i] == ' ' || text[i] == '\t' || text[i] == '\r')) ++i;
  if (i < text.size() && text[i] == '\n') return true;
  // "ply" and CR alone (old Mac line ends): PLY, which the parser reports as such.
  if (i > 3 && text[i - 1] == '\r') return true;
  const std::size_t lf = text.find('\n');
  return lf != std::string_view::npos && text.substr(lf + 1).starts_with("format");
}

PointFileHeader plyHeader(const std::filesystem::path& path) {
  const MappedFile file(path);
  const PlyHeader header = parsePlyHeader(file.bytes(), path.string());
  PointFileHeader out;
  const int element = header.pointElement();
  if (element < 0) return out;
  const PlyElement& points = header.elements[std::size_t(element)];
  out.point_count = points.count;
  out.attributes =
      allocatePointCloud(ply::planPointLayout(points, path.string()), 0, {}).attributeNames();
  return out;
}

std::string plyPropertyType(const PlyProperty& property) {
  if (!property.is_list) return std::string(scalarName(property.type));
  return "list " + std::string(scalarName(property.list_count_type)) + " " +
         std::string(scalarName(property.type));
}

// The header: encoding, version, comments, every element with its count and typed properties.
FormatDescription describePly(const std::filesystem::path& path) {
  // The header is at most kMaxPlyHeaderBytes; parsePlyHeader finds its end in the prefix.
  const std::vector<std::byte> prefix = readPrefix(path, kMaxPlyHeaderBytes);
  const PlyHeader header = parsePlyHeader(prefix, path.string());

  FormatDescription out;
  out.name = "ply";
  out.summary = "PLY " + std::string(plyFormatName(header.format)) + " " + header.version +
                ", header " + std::to_string(header.body_offset) + " bytes";
  for (const auto& comment : header.comments) out.lines.push_back("  comment " + comment);
  for (const auto& info : header.obj_info) out.lines.push_back("  obj_info " + info);
  out.elements = Json::array();
  for (const auto& element : header.elements) {
    std::string line = "  element " + element.name + " " + std::to_string(element.count);
    if (header.format != PlyFormat::Ascii && !element.hasLists()) {
      line += " (" + std::to_string(element.fixedRecordSize()) + " bytes a record)";
    }
    out.lines.push_back(line);
    Json properties = Json::array();
    for (const auto& property : element.properties) {
      out.lines.push_back("    property " + plyPropertyType(property) + " " + property.name);
      Json p = {{"name", property.name}, {"type", std::string(scalarName(property.type))}};
      if (property.is_list) {
        p["list"] = true;
        p["count_type"] = std::string(scalarName(property.list_count_type));
      }
      properties.push_back(std::move(p));
    }
    out.elements.push_back(
        {{"name", element.name}, {"count", element.count}, {"properties", properties}});
  }
  out.details = {{"encoding", std::string(plyFormatName(header.format))},
                 {"version", header.version},
                 {"header_bytes", header.body_offset},
                 {"comments", header.comments},
                 {"obj_info", header.obj_info}};
  return out;
}

PointFormatEntry plyFormat() {
  PointFormatEntry row;
  row.id = "ply";
  row.name = "PLY";
  row.description = "PLY (ascii, binary little and big endian; .ply)";
  row.extensions = {".ply"};
  row.detect = looksLikePly;
  row.header = plyHeader;
  row.read = [](const std::filesystem::path& path, const PointReadOptions& options) {
    return readPly(path, {.progress = options.progress, .parallel = options.parallel});
  };
  row.preview = readPlyPreview;
  row.open_chunks = [](const std::filesystem::path& path, const ChunkSourceOptions& options) {
    auto reader = std::make_unique<PlyChunkReader>(path);
    if (options.quantization) reader->setQuantization(*options.quantization);
    return std::unique_ptr<PointChunkSource>(std::move(reader));
  };
  // Binary bodies are copied (or byte-swapped) into columns; ascii ones are parsed.
  row.rereads_cheaply = [](const std::filesystem::path& path) {
    const MappedFile file(path);
    return parsePlyHeader(file.bytes(), path.string()).format != PlyFormat::Ascii;
  };
  row.describe = describePly;
  row.write = [](const PointCloud& cloud, const std::filesystem::path& path,
                 const PointWriteOptions& options) {
    writePly(cloud, path,
             {.format = options.ply_ascii ? PlyFormat::Ascii : PlyFormat::BinaryLittleEndian,
              .progress = options.progress,
              .properties = options.properties});
  };
  // PLY holds every column of the model: write_losses stays empty.
  return row;
}

// ---------------------------------------------------------------------------------------------
// LAS and LAZ: one header, two encodings of the records.

PointFileHeader lasHeader(const std::filesystem::path& path) {
  const LasHeader header = readLasHeader(path);
  PointFileHeader out;
  out.point_count = header.point_count;
  if (!header.bounds.empty()) out.bounds = header.bounds;
  // A cloud of one point: attributeNames() lists a colour, intensity or classification column
  // only when it holds values (a cloud of 0 points listed the scalars alone).
  out.attributes = allocateLasCloud(header, makeLasDecodePlan(header), 1).attributeNames();
  out.crs = coordinateSystemOf(header);
  return out;
}

// The header's own account (las_header.h): version, point format, scale, offset and bounds
// (shown as the file's bounds beside the computed ones), the CRS, extra bytes; for LAZ the
// compression (compressor, chunking, chunk count, items and their versions).
FormatDescription describeLas(const std::filesystem::path& path) {
  const LasHeader header = readLasHeader(path);
  FormatDescription out;
  out.name = "las";
  std::istringstream lines(describeLasHeader(header));
  std::string line;
  std::getline(lines, out.summary);
  while (std::getline(lines, line)) out.lines.push_back("  " + line);
  Json extra_bytes = Json::array();
  for (const auto& extra : header.extra_bytes) {
    extra_bytes.push_back({{"name", extra.name}, {"type", std::string(scalarName(extra.type))}});
  }
  Json crs = {{"summary", header.crs.summary()}, {"wkt", header.crs.wkt}};
  if (header.crs.projected_epsg) crs["projected_epsg"] = *header.crs.projected_epsg;
  if (header.crs.geographic_epsg) crs["geographic_epsg"] = *header.crs.geographic_epsg;
  if (header.crs.vertical_epsg) crs["vertical_epsg"] = *header.crs.vertical_epsg;
  out.details = {{"version", header.versionString()},
                 {"point_format", header.point_format},
                 {"record_length", header.record_length},
                 {"point_count", header.point_count},
                 {"scale", triple(header.quantization.scale)},
                 {"offset", triple(header.quantization.offset)},
                 {"crs", crs},
                 {"extra_bytes", extra_bytes},
                 {"generating_software", header.generating_software},
                 {"system_identifier", header.system_identifier}};
  if (!header.bounds.empty()) out.declared_bounds = header.bounds;
  if (header.laszip) {
    // LAZ: how the points are compressed (laz_reader.h).
    const LazSummary laz = summarizeLaz(path);
    out.name = "laz";
    std::string items;
    for (const std::string& item : laz.items) items += (items.empty() ? "" : ", ") + item;
    out.lines.push_back(
        "  LAZ " + laz.compressor_name + " (compressor " + std::to_string(laz.compressor) + "), " +
        (laz.chunk_size ? "chunks of " + std::to_string(laz.chunk_size) + " points"
                        : std::string("variable chunks")) +
        ", " + std::to_string(laz.chunks) + " chunks, written by LASzip " + laz.laszip_version +
        (laz.compatibility_mode
             ? ", LAS 1.4 compatibility mode: points of format " + std::to_string(laz.record_format)
             : std::string()));
    out.lines.push_back("  items " + items);
    if (!laz.table_note.empty()) out.lines.push_back("  chunk table: " + laz.table_note);
    out.details["laz"] = {{"compressor", laz.compressor},
                          {"compressor_name", laz.compressor_name},
                          {"chunk_size", laz.chunk_size},
                          {"chunks", laz.chunks},
                          {"laszip_version", laz.laszip_version},
                          {"items", laz.items},
                          {"compatibility_mode", laz.compatibility_mode},
                          {"record_format", laz.record_format},
                          {"chunk_table_note", laz.table_note}};
  }
  return out;
}

// What a LAS or LAZ output keeps of a LAS or LAZ source (PointWriteOptions::source): its whole
// header, every VLR and EVLR, its point format and version (las_writer.h). A WKT CRS is LAS
// 1.4's (global encoding bit 4): from a source of another format, 1.4 is chosen for it unless
// 1.2 was asked for.
struct LasSourceCarry {
  LasWriteOptions options;
  bool wkt_in_12 = false;  // a WKT CRS written to LAS 1.2, which has no flag to say so
};

LasSourceCarry lasCarry(const PointWriteOptions& options) {
  LasSourceCarry carry;
  carry.options.minor_version = options.las_minor_version;
  carry.options.point_format = options.las_point_format;
  carry.options.progress = options.progress;
  if (options.source.empty()) return carry;
  const PointFormat source = detectPointFormat(options.source);
  if (source != PointFormat::Las && source != PointFormat::Laz) return carry;
  auto header = std::make_shared<LasHeader>(readLasHeaderWithRecords(options.source));
  carry.options.gps_time_standard = header->gpsTimeIsStandard();
  carry.options.file_source_id = header->file_source_id;
  const int minor =
      carry.options.minor_version != 0 ? carry.options.minor_version : header->version_minor;
  carry.wkt_in_12 = !header->crs.wkt.empty() && minor < 4;
  carry.options.source = std::move(header);
  return carry;
}

void checkNoPropertyOrder(const std::filesystem::path& path, const PointWriteOptions& options) {
  if (!options.properties.empty()) {
    throw std::invalid_argument(path.string() +
                                ": LAS and LAZ records have a fixed layout, no attribute "
                                "order to choose");
  }
}

std::vector<std::string> lasLosses(const PointCloud& cloud, const std::filesystem::path&,
                                   const PointWriteOptions& options) {
  const LasSourceCarry carry = lasCarry(options);
  std::vector<std::string> losses = planLasWrite(cloud, carry.options).losses;
  if (carry.wkt_in_12) {
    losses.push_back(
        "the WKT coordinate reference system is copied, but LAS 1.2 has no "
        "flag to say it is WKT (use --las-version 1.4)");
  }
  return losses;
}

PointFormatEntry lasRow(std::string id, std::string name, std::string description,
                        std::string extension) {
  PointFormatEntry row;
  row.id = std::move(id);
  row.name = std::move(name);
  row.description = std::move(description);
  row.extensions = {std::move(extension)};
  row.header = lasHeader;
  row.preview = readLasPreview;  // LAS and LAZ alike
  row.describe = describeLas;
  row.write_losses = lasLosses;
  row.writes_crs = true;
  row.fixed_layout = [](const std::filesystem::path&) { return true; };
  return row;
}

PointFormatEntry lasFormat() {
  PointFormatEntry row = lasRow("las", "LAS", "LAS 1.0-1.4, point formats 0-10 (.las)", ".las");
  row.detect = [](std::span<const std::byte> head) {
    return hasLasSignature(head) && !looksLikeLaz(head);
  };
  row.read = [](const std::filesystem::path& path, const PointReadOptions& options) {
    return readLas(path, {.progress = options.progress, .parallel = options.parallel});
  };
  row.open_chunks = [](const std::filesystem::path& path, const ChunkSourceOptions&) {
    // The header's quantization, whatever is asked.
    return std::unique_ptr<PointChunkSource>(std::make_unique<LasChunkReader>(path));
  };
  // Fixed-size records, decoded field by field from the mapped file (lod/NOTES.md "Each point
  // decoded once" for the measurement).
  row.rereads_cheaply = [](const std::filesystem::path&) { return true; };
  row.write = [](const PointCloud& cloud, const std::filesystem::path& path,
                 const PointWriteOptions& options) {
    checkNoPropertyOrder(path, options);
    writeLas(cloud, path, lasCarry(options).options);
  };
  return row;
}

PointFormatEntry lazFormat() {
  PointFormatEntry row =
      lasRow("laz", "LAZ", "LAZ (LASzip-compressed LAS; .laz)", std::string(".laz"));
  // A LAS header's VLRs can lie beyond the first 64 KiB; the reader checks LAZ again in full.
  row.detect = [](std::span<const std::byte> head) {
    return hasLasSignature(head) && looksLikeLaz(head);
  };
  row.read = [](const std::filesystem::path& path, const PointReadOptions& options) {
    return readLaz(path, {.progress = options.progress,
                          .parallel = options.parallel,
                          .attributes = options.attributes});
  };
  row.open_chunks = [](const std::filesystem::path& path, const ChunkSourceOptions& options) {
    return std::unique_ptr<PointChunkSource>(
        std::make_unique<LazChunkReader>(path, options.attributes));
  };
  row.write = [](const PointCloud& cloud, const std::filesystem::path& path,
                 const PointWriteOptions& options) {
    checkNoPropertyOrder(path, options);
    writeLaz(cloud, path,
             {.las = lasCarry(options).options, .chunk_points = options.laz_chunk_points});
  };
  return row;
}

// ---------------------------------------------------------------------------------------------
// Text

PointFormatEntry textFormat() {
  PointFormatEntry row;
  row.id = "text";
  row.name = "text (XYZ/CSV)";
  row.description =
      "text with x y z [r g b ...] a line, separated by blanks, commas or semicolons (.xyz .txt "
      ".csv .asc)";
  row.extensions = {".xyz", ".txt", ".csv", ".asc"};
  // Printable bytes with a line of numbers: tried after every format with a signature.
  row.detect = [](std::span<const std::byte> head) { return looksLikeTextPoints(head); };
  row.fallback = true;
  // A text file states nothing before it is read; its point count takes a pass over the lines.
  row.header = [](const std::filesystem::path&) { return PointFileHeader{}; };
  row.count_points = [](const std::filesystem::path& path) { return countTextPoints(path); };
  row.min_point_bytes = 6;  // "1 2 3\n"
  row.read = [](const std::filesystem::path& path, const PointReadOptions& options) {
    return readText(path, {.columns = options.text_columns,
                           .progress = options.progress,
                           .parallel = options.parallel});
  };
  row.open_chunks = [](const std::filesystem::path& path, const ChunkSourceOptions& options) {
    return std::unique_ptr<PointChunkSource>(std::make_unique<TextChunkReader>(
        path, TextReadOptions{.columns = options.text_columns}, options.quantization));
  };
  row.write = [](const PointCloud& cloud, const std::filesystem::path& path,
                 const PointWriteOptions& options) {
    TextWriteOptions text = textOptionsForPath(path);
    text.progress = options.progress;
    text.properties = options.properties;
    writeText(cloud, path, text);
  };
  row.write_losses = [](const PointCloud& cloud, const std::filesystem::path& path,
                        const PointWriteOptions&) {
    return describeTextLosses(cloud, textOptionsForPath(path));
  };
  return row;
}

// ---------------------------------------------------------------------------------------------
// PCD (pcd_header.h, pcd_reader.h, pcd_writer.h)

std::string formatNumber(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.10g", v);
  return text;
}

// The header alone: version, encoding, fields with size, type and count, grid, viewpoint.
FormatDescription describePcd(const std::filesystem::path& path) {
  const PcdHeader header = parsePcdHeader(readPrefix(path, 1 << 20), path.string());
  FormatDescription out;
  out.name = "pcd";
  out.summary = "PCD " + header.version + " " + pcdDataName(header.data) + ", header " +
                std::to_string(header.data_offset) + " bytes";
  Json fields = Json::array();
  for (const PcdField& f : header.fields) {
    out.lines.push_back("  field " + f.name + " " + f.type + std::to_string(f.size) +
                        (f.count > 1 ? " x " + std::to_string(f.count) : ""));
    fields.push_back(
        {{"name", f.name}, {"type", std::string(1, f.type)}, {"size", f.size}, {"count", f.count}});
  }
  out.lines.push_back("  grid " + std::to_string(header.width) + " x " +
                      std::to_string(header.height) + (header.height > 1 ? " (organised)" : "") +
                      ", " + std::to_string(header.points) + " points with the invalid (NaN) ones");
  std::string viewpoint = "  viewpoint";
  for (double v : header.viewpoint) viewpoint += " " + formatNumber(v);
  out.lines.push_back(viewpoint + " (sensor x y z, qw qx qy qz)");
  out.details = {
      {"version", header.version},    {"data", pcdDataName(header.data)}, {"fields", fields},
      {"width", header.width},        {"height", header.height},          {"points", header.points},
      {"viewpoint", header.viewpoint}};
  return out;
}

PointFormatEntry pcdFormat() {
  PointFormatEntry row;
  row.id = "pcd";
  row.name = "PCD";
  row.description = "PCD (Point Cloud Library: ascii, binary, binary_compressed; .pcd)";
  row.extensions = {".pcd"};
  row.detect = [](std::span<const std::byte> head) { return looksLikePcd(head); };
  row.header = [](const std::filesystem::path& path) {
    PointFileHeader out;
    out.point_count = PcdChunkReader(path).pointCount();  // NaN points not counted
    return out;
  };
  row.read = [](const std::filesystem::path& path, const PointReadOptions& options) {
    return readPcd(path, {.progress = options.progress, .parallel = options.parallel});
  };
  row.open_chunks = [](const std::filesystem::path& path, const ChunkSourceOptions& options) {
    return std::unique_ptr<PointChunkSource>(
        std::make_unique<PcdChunkReader>(path, options.quantization));
  };
  row.describe = describePcd;
  row.write = [](const PointCloud& cloud, const std::filesystem::path& path,
                 const PointWriteOptions& options) {
    writePcd(cloud, path,
             {.data = options.ply_ascii ? PcdData::Ascii : options.pcd_data,
              .progress = options.progress,
              .properties = options.properties});
  };
  // PCD holds every column of the model: write_losses stays empty.
  return row;
}

// ---------------------------------------------------------------------------------------------
// PTX and PTS (ptx_reader.h, ptx_writer.h, pts_reader.h)

FormatDescription describePtx(const std::filesystem::path& path) {
  const std::vector<PtxScan> scans = readPtxScans(path);
  FormatDescription out;
  out.name = "ptx";
  out.summary = "PTX, " + std::to_string(scans.size()) + " scan" + (scans.size() == 1 ? "" : "s");
  Json list = Json::array();
  for (std::size_t i = 0; i < scans.size(); ++i) {
    const PtxScan& scan = scans[i];
    out.lines.push_back("  scan " + std::to_string(i) + ": " + std::to_string(scan.columns) +
                        " x " + std::to_string(scan.rows) + ", " + std::to_string(scan.points) +
                        " points kept, scanner at (" + formatNumber(scan.position[0]) + ", " +
                        formatNumber(scan.position[1]) + ", " + formatNumber(scan.position[2]) +
                        ")");
    list.push_back({{"columns", scan.columns},
                    {"rows", scan.rows},
                    {"points", scan.points},
                    {"position", scan.position},
                    {"transform", scan.transform}});
  }
  out.details = {{"scans", list}};
  return out;
}

PointFormatEntry ptxFormat() {
  PointFormatEntry row;
  row.id = "ptx";
  row.name = "PTX";
  row.description = "PTX (Leica structured text, several scans with their transforms; .ptx)";
  row.extensions = {".ptx"};
  row.detect = [](std::span<const std::byte> head) { return looksLikePtx(head); };
  row.header = [](const std::filesystem::path& path) {
    PointFileHeader out;
    std::uint64_t points = 0;
    for (const PtxScan& scan : readPtxScans(path)) points += scan.points;
    out.point_count = points;
    return out;
  };
  row.read = [](const std::filesystem::path& path, const PointReadOptions& options) {
    return readPtx(path, {.progress = options.progress});
  };
  row.open_chunks = [](const std::filesystem::path& path, const ChunkSourceOptions& options) {
    return std::unique_ptr<PointChunkSource>(
        std::make_unique<PtxChunkReader>(path, options.quantization));
  };
  row.describe = describePtx;
  row.write = [](const PointCloud& cloud, const std::filesystem::path& path,
                 const PointWriteOptions& options) {
    if (!options.properties.empty()) {
      throw std::invalid_argument(path.string() +
                                  ": PTX records have a fixed layout (x y z intensity [r g b]), "
                                  "no attribute order to choose");
    }
    writePtx(cloud, path, {.progress = options.progress});
  };
  row.write_losses = [](const PointCloud& cloud, const std::filesystem::path&,
                        const PointWriteOptions&) {
    std::vector<std::string> losses;
    for (const std::string& name : cloud.attributeNames()) {
      if (name == column_names::kX || name == column_names::kY || name == column_names::kZ ||
          name == column_names::kRed || name == column_names::kGreen ||
          name == column_names::kBlue || name == column_names::kIntensity ||
          name == column_names::kScanIndex) {
        continue;
      }
      losses.push_back(name + " (PTX holds x y z intensity r g b)");
    }
    return losses;
  };
  row.fixed_layout = [](const std::filesystem::path&) { return true; };
  return row;
}

PointFormatEntry ptsFormat() {
  PointFormatEntry row;
  row.id = "pts";
  row.name = "PTS";
  row.description = "PTS (Leica: a count line, then x y z intensity [r g b]; .pts)";
  row.extensions = {".pts"};
  row.detect = [](std::span<const std::byte> head) { return looksLikePts(head); };
  row.header = [](const std::filesystem::path&) { return PointFileHeader{}; };
  row.count_points = [](const std::filesystem::path& path) {
    return countTextPoints(path, {.pts = true});
  };
  row.min_point_bytes = 8;  // "1 2 3 4\n"
  row.read = [](const std::filesystem::path& path, const PointReadOptions& options) {
    return readPts(path, {.progress = options.progress, .parallel = options.parallel});
  };
  row.open_chunks = [](const std::filesystem::path& path, const ChunkSourceOptions& options) {
    return std::unique_ptr<PointChunkSource>(std::make_unique<TextChunkReader>(
        path, TextReadOptions{.columns = options.text_columns, .pts = true}, options.quantization));
  };
  row.write = [](const PointCloud& cloud, const std::filesystem::path& path,
                 const PointWriteOptions& options) {
    TextWriteOptions text = textOptionsForPath(path);
    text.progress = options.progress;
    text.properties = options.properties;  // refused: PTS has a fixed layout
    writeText(cloud, path, text);
  };
  row.write_losses = [](const PointCloud& cloud, const std::filesystem::path& path,
                        const PointWriteOptions&) {
    return describeTextLosses(cloud, textOptionsForPath(path));
  };
  row.fixed_layout = [](const std::filesystem::path&) { return true; };  // x y z i r g b
  return row;
}

}  // namespace

// The table's built-in rows, in detection order: formats with a signature first, text (which
// takes any printable file with numbers) last.
std::vector<PointFormatEntry> builtInPointFormats() {
  std::vector<PointFormatEntry> rows;
  rows.push_back(plyFormat());
  rows.push_back(lasFormat());
  rows.push_back(lazFormat());
  rows.push_back(e57Format());
  rows.push_back(pcdFormat());
  rows.push_back(ptxFormat());
  rows.push_back(ptsFormat());
  rows.push_back(textFormat());
  return rows;
}

}  // namespace parallax
