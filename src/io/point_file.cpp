#include "io/point_file.h"

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <exception>
#include <stdexcept>
#include <utility>

#include "core/error.h"
#include "io/las_header.h"
#include "io/las_reader.h"
#include "io/las_writer.h"
#include "io/laz_reader.h"
#include "io/laz_writer.h"
#include "io/mapped_file.h"
#include "io/partial_output.h"
#include "io/pcd_header.h"
#include "io/pcd_reader.h"
#include "io/pcd_writer.h"
#include "io/ply_header.h"
#include "io/ply_preview.h"
#include "io/ply_reader.h"
#include "io/ply_writer.h"
#include "io/pts_reader.h"
#include "io/ptx_reader.h"
#include "io/ptx_writer.h"
#include "io/text_reader.h"
#include "io/text_writer.h"

namespace parallax {
namespace {

constexpr std::size_t kSniffBytes = 64 << 10;

std::string lowerExtension(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return char(std::tolower(c)); });
  return ext;
}

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

}  // namespace

const char* pointFormatName(PointFormat format) {
  switch (format) {
    case PointFormat::Ply:
      return "PLY";
    case PointFormat::Las:
      return "LAS";
    case PointFormat::Laz:
      return "LAZ";
    case PointFormat::Text:
      return "text (XYZ/CSV)";
    case PointFormat::Pcd:
      return "PCD";
    case PointFormat::Ptx:
      return "PTX";
    case PointFormat::Pts:
      return "PTS";
    case PointFormat::Unknown:
      break;
  }
  return "unknown";
}

const char* supportedFormatsText() {
  return "supported formats: PLY (ascii, binary little and big endian; .ply), LAS 1.0-1.4, "
         "point formats 0-10 (.las), LAZ (LASzip-compressed LAS; .laz), text with x y z [r g b "
         "...] a line, "
         "separated by blanks, commas or semicolons (.xyz .txt .csv .asc), PCD (PCL's format: "
         "ascii, "
         "binary, binary_compressed; .pcd), PTX (Leica, several scans; .ptx), PTS (.pts)";
}

PointFormat detectPointFormatFromMemory(std::span<const std::byte> bytes) {
  if (looksLikePly(bytes)) return PointFormat::Ply;
  if (hasLasSignature(bytes)) return looksLikeLaz(bytes) ? PointFormat::Laz : PointFormat::Las;
  if (looksLikePcd(bytes)) return PointFormat::Pcd;
  if (looksLikePtx(bytes)) return PointFormat::Ptx;
  if (looksLikePts(bytes)) return PointFormat::Pts;
  if (looksLikeTextPoints(bytes)) return PointFormat::Text;
  return PointFormat::Unknown;
}

PointFormat detectPointFormat(const std::filesystem::path& path) {
  std::FILE* file = std::fopen(path.c_str(), "rb");
  if (file == nullptr) {
    throw InputError(
        {.file = path.string(), .expected = "a readable file", .found = std::strerror(errno)});
  }
  std::vector<std::byte> head(kSniffBytes);
  std::size_t got = std::fread(head.data(), 1, head.size(), file);
  std::fclose(file);
  head.resize(got);
  PointFormat format = detectPointFormatFromMemory(head);
  // A LAS header's VLRs can lie beyond the first 64 KiB; the reader checks LAZ again in full.
  // A file named for a structured format whose content is none: its reader says what is wrong
  // (a PCD without its header would otherwise be read as plain text, silently).
  if (format == PointFormat::Text || format == PointFormat::Unknown) {
    const std::string ext = lowerExtension(path);
    if (ext == ".pcd") return PointFormat::Pcd;
    if (ext == ".ptx") return PointFormat::Ptx;
  }
  return format;
}

std::optional<std::uint64_t> headerPointCount(const std::filesystem::path& path) {
  try {
    switch (detectPointFormat(path)) {
      case PointFormat::Ply: {
        const MappedFile file(path);
        const PlyHeader header = parsePlyHeader(file.bytes(), path.string());
        const int element = header.pointElement();
        if (element < 0) return std::nullopt;
        return header.elements[std::size_t(element)].count;
      }
      case PointFormat::Las:
      case PointFormat::Laz:
        return readLasHeader(path).point_count;
      case PointFormat::Pcd: {
        const MappedFile file(path);
        return parsePcdHeader(file.bytes(), path.string()).points;  // NaN points included
      }
      default:
        return std::nullopt;
    }
  } catch (const std::exception&) {
    return std::nullopt;  // the ordinary read says what is wrong
  }
}

PointCloud readPointFile(const std::filesystem::path& path, const PointReadOptions& options) {
  switch (detectPointFormat(path)) {
    case PointFormat::Ply:
      return readPly(path, {.progress = options.progress, .parallel = options.parallel});
    case PointFormat::Las:
      return readLas(path, {.progress = options.progress, .parallel = options.parallel});
    case PointFormat::Laz:
      return readLaz(path, {.progress = options.progress, .parallel = options.parallel});
    case PointFormat::Text:
      return readText(path, {.columns = options.text_columns,
                             .progress = options.progress,
                             .parallel = options.parallel});
    case PointFormat::Pcd:
      return readPcd(path, {.progress = options.progress, .parallel = options.parallel});
    case PointFormat::Ptx:
      return readPtx(path, {.progress = options.progress});
    case PointFormat::Pts:
      return readPts(path, {.progress = options.progress, .parallel = options.parallel});
    default:
      break;
  }
  const std::string hint = supportedFormatsText();
  throw InputError({.file = path.string(),
                    .byte_offset = 0,
                    .expected = "a point cloud file",
                    .found = "an unknown format",
                    .hint = hint});
}

bool hasPointFilePreview(PointFormat format) {
  return format == PointFormat::Ply || format == PointFormat::Las || format == PointFormat::Laz;
}

PointCloud readPointFilePreview(const std::filesystem::path& path, std::uint64_t max_points) {
  const PointFormat format = detectPointFormat(path);
  if (format == PointFormat::Ply) return readPlyPreview(path, max_points);
  if (format == PointFormat::Las || format == PointFormat::Laz) {
    return readLasPreview(path, max_points);
  }
  throw InputError({.file = path.string(),
                    .expected = "a PLY, LAS or LAZ file (a sample is read from those only)",
                    .found = pointFormatName(format)});
}

PointFormat formatForExtension(const std::filesystem::path& path) {
  std::string ext = lowerExtension(path);
  if (ext == ".ply") return PointFormat::Ply;
  if (ext == ".las") return PointFormat::Las;
  if (ext == ".laz") return PointFormat::Laz;
  if (ext == ".xyz" || ext == ".txt" || ext == ".csv" || ext == ".asc") return PointFormat::Text;
  if (ext == ".pcd") return PointFormat::Pcd;
  if (ext == ".ptx") return PointFormat::Ptx;
  if (ext == ".pts") return PointFormat::Pts;
  return PointFormat::Unknown;
}

std::vector<std::string> describeWriteLosses(const PointCloud& cloud,
                                             const std::filesystem::path& path,
                                             const PointWriteOptions& options) {
  switch (formatForExtension(path)) {
    case PointFormat::Las:
    case PointFormat::Laz:
      return planLasWrite(cloud, {.minor_version = options.las_minor_version}).losses;
    case PointFormat::Text:
    case PointFormat::Pts:
      return describeTextLosses(cloud, textOptionsForPath(path));
    default:
      return {};  // PLY holds every column of the model
  }
}

void writePointFile(const PointCloud& cloud, const std::filesystem::path& path,
                    const PointWriteOptions& options) {
  switch (formatForExtension(path)) {
    case PointFormat::Ply:
      writePly(cloud, path,
               {.format = options.ply_ascii ? PlyFormat::Ascii : PlyFormat::BinaryLittleEndian,
                .progress = options.progress,
                .properties = options.properties});
      return;
    case PointFormat::Las:
    case PointFormat::Laz:
      if (!options.properties.empty()) {
        throw std::invalid_argument(path.string() +
                                    ": LAS and LAZ records have a fixed layout, no attribute "
                                    "order to choose");
      }
      if (formatForExtension(path) == PointFormat::Laz) {
        writeLaz(cloud, path,
                 {.las = {.minor_version = options.las_minor_version, .progress = options.progress},
                  .chunk_points = options.laz_chunk_points});
        return;
      }
      writeLas(cloud, path,
               {.minor_version = options.las_minor_version, .progress = options.progress});
      return;
    case PointFormat::Ptx:
      writePtx(cloud, path, {.progress = options.progress});
      return;
    case PointFormat::Text:
    case PointFormat::Pts: {
      TextWriteOptions text = textOptionsForPath(path);
      text.progress = options.progress;
      text.properties = options.properties;
      writeText(cloud, path, text);
      return;
    }
    case PointFormat::Pcd:
      writePcd(cloud, path,
               {.data = options.ply_ascii ? PcdData::Ascii : options.pcd_data,
                .progress = options.progress,
                .properties = options.properties});
      return;
    default:
      break;
  }
  throw InputError({.file = path.string(),
                    .expected = "an output name ending in .ply, .las, .laz, .xyz, .txt, .csv, "
                                ".asc, .pts, .pcd or .ptx",
                    .found = "'" + path.extension().string() + "'",
                    .hint = supportedFormatsText()});
}

OutputFile::OutputFile(const std::filesystem::path& path) : path_(path) {
  // A hidden ".NAME.partial-PID-N" beside the target (partial_output.h), unique per writer.
  temp_ = newPartialFilePath(path);
  file_ = std::fopen(temp_.c_str(), "wb");
  if (file_ == nullptr) fail("cannot create");
  std::setvbuf(file_, nullptr, _IOFBF, 1 << 20);
}

OutputFile::~OutputFile() {
  if (committed_) return;
  if (file_) std::fclose(file_);
  std::error_code ignored;
  std::filesystem::remove(temp_, ignored);
}

void OutputFile::fail(const char* what) {
  throw std::runtime_error(std::string(what) + " '" + temp_.string() + "' (for '" + path_.string() +
                           "'): " + std::strerror(errno));
}

void OutputFile::write(const void* data, std::size_t size) {
  if (size != 0 && std::fwrite(data, 1, size, file_) != size) fail("cannot write");
}

void OutputFile::writeAt(std::uint64_t offset, const void* data, std::size_t size) {
  if (std::fflush(file_) != 0) fail("cannot write");
  long back = std::ftell(file_);
  if (back < 0 || std::fseek(file_, long(offset), SEEK_SET) != 0) fail("cannot seek in");
  write(data, size);
  if (std::fflush(file_) != 0 || std::fseek(file_, back, SEEK_SET) != 0) fail("cannot seek in");
}

void OutputFile::commit() {
  std::FILE* file = std::exchange(file_, nullptr);
  if (std::fclose(file) != 0) fail("cannot write");
  std::error_code error;
  std::filesystem::rename(temp_, path_, error);
  if (error) {
    throw std::runtime_error("cannot rename '" + temp_.string() + "' to '" + path_.string() +
                             "': " + error.message());
  }
  committed_ = true;
}

}  // namespace parallax
