// Reading PCD files: header, a view of where each value lies, then two passes over ranges of
// records in parallel: positions (valid points and their exact bounds, so the quantization is
// exact before any point is stored and each range knows where its points go), then every column.
// The positions pass reads 12 or 24 bytes a record from memory the decode reads again while it is
// still in the caches' reach of the page cache; it costs far less than choosing a quantization
// from a sample and decoding twice when the sample was wrong (the PLY reader's way), and NaN
// points make the count unknown without it anyway.
#include "io/pcd_reader.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <numeric>
#include <vector>

#include "core/error.h"
#include "core/quantization.h"
#include "io/mapped_file.h"
#include "io/pcd_decoder.h"

namespace parallax {
namespace {

using pcd::DataView;
using pcd::PositionScan;

constexpr std::uint64_t kRangeRecords = 1 << 14;
constexpr std::uint64_t kAsciiChunkRecords = 1 << 16;

// Where the binary data ends short: the point and the field the last byte falls in.
[[noreturn]] void failTruncated(const PcdHeader& header, std::size_t file_size,
                                const std::string& file) {
  const std::uint64_t have = file_size - std::min(file_size, header.data_offset);
  const std::uint64_t point = have / header.record_size;
  const std::uint64_t in_record = have % header.record_size;
  std::string field = header.fields.front().name;
  for (const PcdField& f : header.fields) {
    if (f.offset <= in_record) field = f.name;
  }
  throw InputError({.file = file,
                    .byte_offset = file_size,
                    .element = "point " + std::to_string(point),
                    .property = field,
                    .expected = std::to_string(header.points * header.record_size) +
                                " bytes of binary data (" + std::to_string(header.points) +
                                " points of " + std::to_string(header.record_size) + " bytes)",
                    .found = std::to_string(have) + " bytes: the file ends inside point " +
                             std::to_string(point),
                    .hint = "the file is truncated, or POINTS/WIDTH/HEIGHT are wrong"});
}

// The data of a PCD file: the view over it, and what holds the bytes the view points into.
struct PcdSource {
  PcdHeader header;
  pcd::Layout layout;
  std::vector<std::byte> decompressed;  // binary_compressed
  pcd::AsciiTable ascii;                // ascii, parsed whole (readPcd) or a chunk at a time
  DataView view;
};

void openData(std::span<const std::byte> bytes, const std::string& name, PcdSource& data,
              bool parse_ascii) {
  data.header = parsePcdHeader(bytes, name);
  data.layout = pcd::mapFields(data.header, name);
  const PcdHeader& header = data.header;
  if (header.data == PcdData::Binary) {
    if (header.record_size == 0 ||
        (bytes.size() - header.data_offset) / header.record_size < header.points) {
      if (header.points != 0) failTruncated(header, bytes.size(), name);
    }
    data.view =
        pcd::binaryView(header, data.layout, bytes.data() + header.data_offset, header.points);
  } else if (header.data == PcdData::BinaryCompressed) {
    pcd::decompress(bytes, header, name, data.decompressed);
    data.view = pcd::compressedView(header, data.layout, data.decompressed.data(), header.points);
  } else if (parse_ascii) {
    const std::string_view text(reinterpret_cast<const char*>(bytes.data()), bytes.size());
    data.ascii = pcd::parseAscii(text, header.data_offset, header.data_line, header.points,
                                 data.layout, name);
    if (data.ascii.records != header.points) {
      throw InputError({.file = name,
                        .line = data.ascii.next_line,
                        .element = "ascii data",
                        .expected = std::to_string(header.points) + " points (POINTS)",
                        .found = std::to_string(data.ascii.records) + " lines of data",
                        .hint = "the file is truncated, or POINTS/WIDTH/HEIGHT are wrong"});
    }
    const std::string_view rest = text.substr(data.ascii.end);
    if (rest.find_first_not_of(" \t\r\n") != std::string_view::npos) {
      throw InputError({.file = name,
                        .line = data.ascii.next_line,
                        .element = "ascii data",
                        .expected = "the end of the file after " + std::to_string(header.points) +
                                    " points (POINTS)",
                        .found = "more lines",
                        .hint = "POINTS/WIDTH/HEIGHT are smaller than the data"});
    }
    data.view = data.ascii.view(data.layout);
  }
}

PointCloud decodeAll(const PcdSource& data, const MappedFile* mapping,
                     const PcdReadOptions& options) {
  const std::uint64_t records = data.view.records;
  const std::uint64_t range_count = (records + kRangeRecords - 1) / kRangeRecords;
  std::vector<PositionScan> scans(range_count);
  auto forRanges = [&](auto&& body) {
    if (options.parallel && range_count > 1) {
      tbb::parallel_for(std::uint64_t(0), range_count, body);
    } else {
      for (std::uint64_t r = 0; r < range_count; ++r) body(r);
    }
  };
  auto rangeEnd = [&](std::uint64_t r) { return std::min(records, (r + 1) * kRangeRecords); };
  forRanges([&](std::uint64_t r) {
    scans[r] = pcd::scanPositions(data.view, data.layout, r * kRangeRecords, rangeEnd(r));
  });
  Bounds3 bounds;
  std::vector<std::uint64_t> first(range_count + 1, 0);
  pcd::Layout layout = data.layout;
  for (std::uint64_t r = 0; r < range_count; ++r) {
    bounds.extend(scans[r].bounds);
    first[r + 1] = first[r] + scans[r].valid;
    if (scans[r].color_above_255) layout.colors_8bit = false;
  }
  PointCloud cloud = pcd::allocateCloud(layout, first[range_count], chooseQuantization(bounds));
  const bool binary = data.header.data == PcdData::Binary;
  forRanges([&](std::uint64_t r) {
    const std::uint64_t begin = r * kRangeRecords, end = rangeEnd(r);
    pcd::decodeRecords(data.view, layout, begin, end, scans[r].valid, cloud, first[r]);
    if (binary && mapping != nullptr) {
      mapping->releaseRead(data.header.data_offset + begin * data.header.record_size,
                           (end - begin) * data.header.record_size);
    }
    if (options.progress) options.progress->advance(end - begin);
  });
  cloud.computeBounds();
  return cloud;
}

PointCloud readPcdBytes(std::span<const std::byte> bytes, const std::string& name,
                        const MappedFile* mapping, const PcdReadOptions& options) {
  PcdSource data;
  openData(bytes, name, data, true);
  return decodeAll(data, mapping, options);
}

}  // namespace

PointCloud readPcd(const std::filesystem::path& path, const PcdReadOptions& options) {
  const MappedFile file(path);
  return readPcdBytes(file.bytes(), path.string(), &file, options);
}

PointCloud readPcdFromMemory(std::span<const std::byte> bytes, const std::string& name,
                             const PcdReadOptions& options) {
  return readPcdBytes(bytes, name, nullptr, options);
}

struct PcdChunkReader::State {
  MappedFile file;
  PcdSource data;
  Quantization quantization;
  std::uint64_t valid = 0;
  std::uint64_t next_record = 0;
  // ascii: where the next chunk's lines start
  std::size_t next_offset = 0;
  std::uint64_t next_line = 0;

  explicit State(const std::filesystem::path& path) : file(path) {}

  std::string_view text() const {
    return {reinterpret_cast<const char*>(file.bytes().data()), file.size()};
  }
  bool ascii() const { return data.header.data == PcdData::Ascii; }

  // The next chunk of up to `max` records of ascii data, parsed (the view follows it).
  std::uint64_t parseAsciiChunk(std::uint64_t max) {
    data.ascii = pcd::parseAscii(text(), next_offset, next_line, max, data.layout, file.path());
    data.view = data.ascii.view(data.layout);
    next_offset = data.ascii.end;
    next_line = data.ascii.next_line;
    return data.ascii.records;
  }
};

PcdChunkReader::PcdChunkReader(const std::filesystem::path& path, const Quantization* quantization)
    : state_(std::make_unique<State>(path)) {
  State& s = *state_;
  openData(s.file.bytes(), path.string(), s.data, false);
  Bounds3 bounds;
  if (s.ascii()) {
    // A first pass over the lines (parsed, checked, dropped) for the valid count and bounds.
    s.next_offset = s.data.header.data_offset;
    s.next_line = s.data.header.data_line;
    std::uint64_t records = 0;
    while (records < s.data.header.points) {
      const std::uint64_t got =
          s.parseAsciiChunk(std::min(kAsciiChunkRecords, s.data.header.points - records));
      if (got == 0) break;
      const PositionScan scan = pcd::scanPositions(s.data.view, s.data.layout, 0, got);
      s.valid += scan.valid;
      if (scan.color_above_255) s.data.layout.colors_8bit = false;
      bounds.extend(scan.bounds);
      records += got;
    }
    if (records != s.data.header.points) {
      throw InputError({.file = path.string(),
                        .line = s.next_line,
                        .element = "ascii data",
                        .expected = std::to_string(s.data.header.points) + " points (POINTS)",
                        .found = std::to_string(records) + " lines of data"});
    }
    s.next_offset = s.data.header.data_offset;
    s.next_line = s.data.header.data_line;
  } else {
    const PositionScan scan =
        pcd::scanPositions(s.data.view, s.data.layout, 0, s.data.view.records);
    s.valid = scan.valid;
    bounds = scan.bounds;
    if (scan.color_above_255) s.data.layout.colors_8bit = false;
  }
  s.quantization = quantization ? *quantization : chooseQuantization(bounds);
}

PcdChunkReader::~PcdChunkReader() = default;
PcdChunkReader::PcdChunkReader(PcdChunkReader&&) noexcept = default;

const PcdHeader& PcdChunkReader::header() const {
  return state_->data.header;
}

std::uint64_t PcdChunkReader::pointCount() const {
  return state_->valid;
}

const Quantization& PcdChunkReader::quantization() const {
  return state_->quantization;
}

bool PcdChunkReader::next(PointCloud& chunk, std::size_t max_points) {
  State& s = *state_;
  const std::uint64_t total = s.data.header.points;
  while (s.next_record < total) {
    const std::uint64_t want = std::min<std::uint64_t>(max_points, total - s.next_record);
    std::uint64_t begin = s.next_record, end = s.next_record + want;
    if (s.ascii()) {
      const std::uint64_t got = s.parseAsciiChunk(want);
      begin = 0, end = got;
      if (got == 0) break;
      s.next_record += got;
    } else {
      s.next_record = end;
    }
    const PositionScan scan = pcd::scanPositions(s.data.view, s.data.layout, begin, end);
    if (scan.valid == 0) continue;  // a run of invalid points
    for (int axis = 0; axis < 3; ++axis) {
      if (!s.quantization.fits(axis, scan.bounds.min[axis]) ||
          !s.quantization.fits(axis, scan.bounds.max[axis])) {
        throw InputError({.file = s.file.path(),
                          .element = "points " + std::to_string(s.next_record - (end - begin)) +
                                     " to " + std::to_string(s.next_record),
                          .property = std::string(1, char('x' + axis)),
                          .expected = "positions within the quantization given",
                          .found = "a position outside it"});
      }
    }
    chunk = pcd::allocateCloud(s.data.layout, scan.valid, s.quantization);
    pcd::decodeRecords(s.data.view, s.data.layout, begin, end, scan.valid, chunk, 0);
    chunk.computeBounds();
    return true;
  }
  chunk = PointCloud{};
  chunk.quantization = s.quantization;
  return false;
}

}  // namespace parallax
