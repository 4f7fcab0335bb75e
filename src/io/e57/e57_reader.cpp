#include "io/e57/e57_reader.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <optional>

#include "core/error.h"
#include "io/e57/e57_pages.h"
#include "io/e57/e57_records.h"
#include "io/mapped_file.h"

namespace parallax {
namespace {

// Decoding in batches keeps the fields' value arrays in cache whatever the chunk size.
constexpr std::size_t kBatchRecords = 16384;

std::uint32_t loadLe32(const std::byte* p) {
  std::uint32_t v = 0;
  for (int i = 3; i >= 0; --i) v = v << 8 | std::uint32_t(p[i]);
  return v;
}
std::uint64_t loadLe64(const std::byte* p) {
  std::uint64_t v = 0;
  for (int i = 7; i >= 0; --i) v = v << 8 | std::uint64_t(p[i]);
  return v;
}

// A declared range is usable for bounds when it is finite and not a type's whole range (the
// default a writer leaves when it states nothing).
bool usableRange(double lo, double hi) {
  return std::isfinite(lo) && std::isfinite(hi) && lo <= hi && hi - lo < 1e30;
}

bool isStateField(const std::string& name) {
  return name == "cartesianInvalidState" || name == "sphericalInvalidState" ||
         name == "isColorInvalid" || name == "isIntensityInvalid";
}

bool isMappedField(const std::string& name) {
  return name.starts_with("cartesian") || name.starts_with("spherical") || name == "intensity" ||
         name == "colorRed" || name == "colorGreen" || name == "colorBlue" || isStateField(name);
}

// Thrown when a point lies outside the bounds the file declares; readE57 then measures them.
class OutsideDeclaredBounds : public InputError {
 public:
  using InputError::InputError;
};

struct Channel {
  double minimum = 0.0;
  double factor = 1.0;  // output = (value - minimum) * factor
  bool raw = true;      // output = value
};

struct ScanLayout {
  bool spherical = false;
  int position[3] = {-1, -1, -1};
  int invalid_state = -1;
  int intensity = -1, intensity_invalid = -1;
  int color[3] = {-1, -1, -1};
  int color_invalid = -1;
  Channel intensity_map;
  Channel color_map[3];
  std::vector<std::pair<int, int>> extras;  // (field, extra column)
  std::array<double, 9> rotation{};
  std::array<double, 3> translation{};
  bool identity = true;
};

struct ExtraColumn {
  std::string name;
  ScalarType type = ScalarType::Int32;
};

int fieldIndex(const E57Scan& scan, std::string_view name) {
  for (std::size_t i = 0; i < scan.fields.size(); ++i) {
    if (scan.fields[i].name == name) return int(i);
  }
  return -1;
}

}  // namespace

struct E57ChunkReader::State {
  std::optional<MappedFile> mapped;
  std::optional<E57Pages> pages;
  E57Header header;
  Quantization quantization;
  std::vector<ScanLayout> layouts;
  std::vector<ExtraColumn> extras;
  Progress* progress = nullptr;

  std::size_t current_scan = 0;  // the scan being decoded
  std::unique_ptr<E57RecordDecoder> decoder;
  std::uint64_t per_scan_limit = std::numeric_limits<std::uint64_t>::max();
  std::uint64_t scan_records_done = 0;
  std::vector<std::vector<double>> values;
  std::vector<bool> wanted;

  void open(std::span<const std::byte> bytes, const std::string& name);
  void buildLayouts();
  std::optional<Bounds3> declaredBounds() const;
  Bounds3 measureBounds();
  // Decodes the next at most `count` records of the current scan into `values`; 0 at the end of
  // the file. `positions_only` skips nothing in the file but leaves colours etc. unconverted.
  std::size_t decodeBatch(std::size_t count, bool positions_only);
  bool position(const ScanLayout& layout, std::size_t i, double out[3]) const;
};

void E57ChunkReader::State::open(std::span<const std::byte> bytes, const std::string& name) {
  if (bytes.size() < kE57FileHeaderSize || std::memcmp(bytes.data(), kE57Signature, 8) != 0) {
    throw InputError({.file = name,
                      .byte_offset = 0,
                      .element = "E57 file header",
                      .property = "signature",
                      .expected = "\"ASTM-E57\"",
                      .found = bytes.size() < 8
                                   ? "a file of " + std::to_string(bytes.size()) + " bytes"
                                   : quoteInput({reinterpret_cast<const char*>(bytes.data()), 8})});
  }
  const std::byte* raw = bytes.data();
  const std::uint64_t declared_length = loadLe64(raw + 16);
  const std::uint64_t page_size = loadLe64(raw + 40);
  auto bad_header = [&](std::uint64_t offset, const char* property, const std::string& expected,
                        const std::string& found, const std::string& hint = {}) {
    throw InputError({.file = name,
                      .byte_offset = offset,
                      .element = "E57 file header",
                      .property = property,
                      .expected = expected,
                      .found = found,
                      .hint = hint});
  };
  if (page_size != kE57PageSize) {
    bad_header(40, "pageSize", "1024", std::to_string(page_size));
  }
  if (declared_length != bytes.size()) {
    bad_header(16, "filePhysicalLength", std::to_string(declared_length) + " bytes (the header's)",
               "a file of " + std::to_string(bytes.size()) + " bytes",
               declared_length > bytes.size() ? "the file is truncated" : "");
  }
  pages.emplace(bytes, name);
  std::byte head[kE57FileHeaderSize];
  pages->read(0, head, "E57 file header");
  header.version_major = loadLe32(head + 8);
  header.version_minor = loadLe32(head + 12);
  if (header.version_major != 1) {
    bad_header(8, "majorVersion", "1", std::to_string(header.version_major));
  }
  const std::uint64_t xml_physical = loadLe64(head + 24);
  const std::uint64_t xml_length = loadLe64(head + 32);
  const std::uint64_t xml_logical = e57PhysicalToLogical(xml_physical);
  if (xml_physical % kE57PageSize >= kE57PageData || xml_logical > pages->logicalSize() ||
      xml_length > pages->logicalSize() - xml_logical || xml_length == 0) {
    bad_header(24, "xmlPhysicalOffset, xmlLogicalLength", "an XML section inside the file",
               std::to_string(xml_length) + " bytes at " + std::to_string(xml_physical));
  }
  std::string xml(xml_length, '\0');
  pages->read(xml_logical, {reinterpret_cast<std::byte*>(xml.data()), xml.size()}, "XML section");
  header.document = parseE57Document(xml, name, xml_physical);
  for (const E57Scan& each : header.document.scans) header.record_count += each.record_count;
  buildLayouts();
  if (auto bounds = declaredBounds()) {
    header.bounds = *bounds;
  } else {
    header.bounds = measureBounds();
    header.bounds_measured = true;
  }
  // A little margin: corners moved by a pose are rounded, and a writer's bounds may be rounded.
  quantization = chooseQuantization(header.bounds, 1.001);
}

void E57ChunkReader::State::buildLayouts() {
  bool wide_color = false;
  for (const E57Scan& scan : header.document.scans) {
    ScanLayout layout;
    const int cartesian = fieldIndex(scan, "cartesianX");
    layout.spherical = cartesian < 0;
    const char* names[2][3] = {{"cartesianX", "cartesianY", "cartesianZ"},
                               {"sphericalRange", "sphericalAzimuth", "sphericalElevation"}};
    for (int a = 0; a < 3; ++a) layout.position[a] = fieldIndex(scan, names[layout.spherical][a]);
    layout.invalid_state =
        fieldIndex(scan, layout.spherical ? "sphericalInvalidState" : "cartesianInvalidState");
    layout.intensity = fieldIndex(scan, "intensity");
    layout.intensity_invalid = fieldIndex(scan, "isIntensityInvalid");
    layout.color_invalid = fieldIndex(scan, "isColorInvalid");
    if (layout.intensity >= 0) {
      header.has_intensity = true;
      const E57Field& field = scan.fields[std::size_t(layout.intensity)];
      std::optional<std::array<double, 2>> limits = scan.intensity_limits;
      if (!limits && field.kind != E57Field::Kind::Float && field.lowest() < field.highest()) {
        limits = std::array<double, 2>{field.lowest(), field.highest()};
      }
      if (limits) {
        layout.intensity_map = {(*limits)[0], 65535.0 / ((*limits)[1] - (*limits)[0]), false};
      }
    }
    const char* color_names[3] = {"colorRed", "colorGreen", "colorBlue"};
    for (int c = 0; c < 3; ++c) layout.color[c] = fieldIndex(scan, color_names[c]);
    if (layout.color[0] >= 0 && layout.color[1] >= 0 && layout.color[2] >= 0) {
      header.has_colors = true;
      for (int c = 0; c < 3; ++c) {
        const E57Field& field = scan.fields[std::size_t(layout.color[c])];
        double lo = 0.0, hi = 255.0;
        if (scan.color_limits) {
          lo = (*scan.color_limits)[2 * c], hi = (*scan.color_limits)[2 * c + 1];
        } else if (field.lowest() < field.highest() &&
                   usableRange(field.lowest(), field.highest())) {
          lo = field.lowest(), hi = field.highest();
        } else if (field.kind == E57Field::Kind::Float) {
          lo = 0.0, hi = 1.0;
        }
        wide_color = wide_color || hi - lo > 255.0;
        layout.color_map[c] = {lo, 255.0 / (hi - lo), false};
      }
    } else {
      for (int& c : layout.color) c = -1;
    }
    for (std::size_t f = 0; f < scan.fields.size(); ++f) {
      const E57Field& field = scan.fields[f];
      if (isMappedField(field.name) || field.kind == E57Field::Kind::String) continue;
      auto known = std::find_if(extras.begin(), extras.end(),
                                [&](const ExtraColumn& e) { return e.name == field.name; });
      const bool fits_int32 = field.kind == E57Field::Kind::Integer &&
                              field.minimum >= std::numeric_limits<std::int32_t>::min() &&
                              field.maximum <= std::numeric_limits<std::int32_t>::max();
      if (known == extras.end()) {
        extras.push_back({field.name, fits_int32 ? ScalarType::Int32 : ScalarType::Float64});
        known = extras.end() - 1;
      } else if (!fits_int32) {
        known->type = ScalarType::Float64;
      }
      layout.extras.emplace_back(int(f), int(known - extras.begin()));
    }
    const auto& pose = scan.pose;
    layout.rotation = pose.matrix();
    layout.translation = pose.translation;
    layout.identity = pose.rotation == std::array<double, 4>{1.0, 0.0, 0.0, 0.0} &&
                      pose.translation == std::array<double, 3>{0.0, 0.0, 0.0};
    layouts.push_back(std::move(layout));
  }
  PointCloud probe;
  probe.colors = Column<Rgba8>(header.has_colors ? 1 : 0);
  probe.intensity = Column<float>(header.has_intensity ? 1 : 0);
  probe.count = 1;
  probe.scalars.push_back({column_names::kScanIndex, ScalarType::UInt32, {}});
  for (const ExtraColumn& extra : extras) probe.scalars.push_back({extra.name, extra.type, {}});
  header.attributes = probe.attributeNames();
  (void)wide_color;
}

std::optional<Bounds3> E57ChunkReader::State::declaredBounds() const {
  Bounds3 world;
  for (std::size_t s = 0; s < layouts.size(); ++s) {
    const E57Scan& scan = header.document.scans[s];
    const ScanLayout& layout = layouts[s];
    if (scan.record_count == 0) continue;
    Bounds3 local;
    if (!layout.spherical && scan.cartesian_bounds) {
      local = *scan.cartesian_bounds;
    } else if (!layout.spherical) {
      for (int a = 0; a < 3; ++a) {
        const E57Field& field = scan.fields[std::size_t(layout.position[a])];
        if (!usableRange(field.lowest(), field.highest())) return std::nullopt;
        local.min[a] = field.lowest(), local.max[a] = field.highest();
      }
    } else {
      double range = scan.range_maximum.value_or(-1.0);
      const E57Field& field = scan.fields[std::size_t(layout.position[0])];
      if (range < 0 && usableRange(field.lowest(), field.highest())) {
        range = std::max(std::abs(field.lowest()), std::abs(field.highest()));
      }
      if (range < 0) return std::nullopt;
      local.extend(-range, -range, -range);
      local.extend(range, range, range);
    }
    for (int corner = 0; corner < 8; ++corner) {
      const double p[3] = {corner & 1 ? local.max[0] : local.min[0],
                           corner & 2 ? local.max[1] : local.min[1],
                           corner & 4 ? local.max[2] : local.min[2]};
      const auto& r = layout.rotation;
      const auto& t = layout.translation;
      world.extend(r[0] * p[0] + r[1] * p[1] + r[2] * p[2] + t[0],
                   r[3] * p[0] + r[4] * p[1] + r[5] * p[2] + t[1],
                   r[6] * p[0] + r[7] * p[1] + r[8] * p[2] + t[2]);
    }
  }
  return world;
}

bool E57ChunkReader::State::position(const ScanLayout& layout, std::size_t i, double out[3]) const {
  if (layout.invalid_state >= 0 && values[std::size_t(layout.invalid_state)][i] != 0.0) {
    return false;
  }
  double p[3];
  if (layout.spherical) {
    const double range = values[std::size_t(layout.position[0])][i];
    const double azimuth = values[std::size_t(layout.position[1])][i];
    const double elevation = values[std::size_t(layout.position[2])][i];
    const double planar = range * std::cos(elevation);
    p[0] = planar * std::cos(azimuth), p[1] = planar * std::sin(azimuth);
    p[2] = range * std::sin(elevation);
  } else {
    for (int a = 0; a < 3; ++a) p[a] = values[std::size_t(layout.position[a])][i];
  }
  if (layout.identity) {
    out[0] = p[0], out[1] = p[1], out[2] = p[2];
  } else {
    const auto& r = layout.rotation;
    const auto& t = layout.translation;
    out[0] = r[0] * p[0] + r[1] * p[1] + r[2] * p[2] + t[0];
    out[1] = r[3] * p[0] + r[4] * p[1] + r[5] * p[2] + t[1];
    out[2] = r[6] * p[0] + r[7] * p[1] + r[8] * p[2] + t[2];
  }
  return true;
}

std::size_t E57ChunkReader::State::decodeBatch(std::size_t count, bool positions_only) {
  while (current_scan < layouts.size()) {
    const E57Scan& info = header.document.scans[current_scan];
    if (!decoder) {
      decoder = std::make_unique<E57RecordDecoder>(*pages, info, current_scan);
      scan_records_done = 0;
    }
    const std::uint64_t left = std::min(
        decoder->remaining(), per_scan_limit - std::min(per_scan_limit, scan_records_done));
    if (left == 0) {
      decoder.reset();
      ++current_scan;
      continue;
    }
    const ScanLayout& layout = layouts[current_scan];
    wanted.assign(info.fields.size(), !positions_only);
    for (int f : layout.position) wanted[std::size_t(f)] = true;
    if (layout.invalid_state >= 0) wanted[std::size_t(layout.invalid_state)] = true;
    const std::size_t n = std::size_t(std::min<std::uint64_t>(left, count));
    decoder->decode(n, wanted, values);
    scan_records_done += n;
    if (progress) progress->advance(n);
    return n;
  }
  return 0;
}

Bounds3 E57ChunkReader::State::measureBounds() {
  Bounds3 bounds;
  const std::size_t saved_scan = current_scan;
  current_scan = 0;
  decoder.reset();
  Progress* saved_progress = progress;
  progress = nullptr;
  while (const std::size_t n = decodeBatch(kBatchRecords, true)) {
    const ScanLayout& layout = layouts[current_scan];
    for (std::size_t i = 0; i < n; ++i) {
      double p[3];
      if (!position(layout, i, p)) continue;
      if (std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2])) {
        bounds.extend(p[0], p[1], p[2]);
      }
    }
  }
  current_scan = saved_scan;
  decoder.reset();
  progress = saved_progress;
  return bounds;
}

bool looksLikeE57(std::span<const std::byte> bytes) {
  return bytes.size() >= 8 && std::memcmp(bytes.data(), kE57Signature, 8) == 0;
}

E57ChunkReader::E57ChunkReader(const std::filesystem::path& path)
    : state_(std::make_unique<State>()) {
  state_->mapped.emplace(path);
  state_->open(state_->mapped->bytes(), state_->mapped->path());
}

E57ChunkReader::E57ChunkReader(std::span<const std::byte> bytes, const std::string& name)
    : state_(std::make_unique<State>()) {
  state_->open(bytes, name);
}

E57ChunkReader::~E57ChunkReader() = default;
E57ChunkReader::E57ChunkReader(E57ChunkReader&&) noexcept = default;

const E57Header& E57ChunkReader::header() const {
  return state_->header;
}
std::uint64_t E57ChunkReader::pointCount() const {
  return state_->header.record_count;
}
const Quantization& E57ChunkReader::quantization() const {
  return state_->quantization;
}
void E57ChunkReader::setQuantization(const Quantization& quantization) {
  state_->quantization = quantization;
}
void E57ChunkReader::setProgress(Progress* progress) {
  state_->progress = progress;
}
void E57ChunkReader::measureBounds() {
  state_->header.bounds = state_->measureBounds();
  state_->header.bounds_measured = true;
  state_->quantization = chooseQuantization(state_->header.bounds, 1.001);
}
void E57ChunkReader::limitRecordsPerScan(std::uint64_t records) {
  state_->per_scan_limit = records;
}

namespace {

// Columns sized for `capacity` points, cut to `count` (fewer when invalid points were skipped).
template <class T>
Column<T> cut(Column<T>&& column, std::size_t count) {
  if (column.size() == count) return std::move(column);
  Column<T> shorter(count);
  std::copy_n(column.begin(), count, shorter.begin());
  return shorter;
}

ByteBuffer cut(ByteBuffer&& buffer, std::size_t bytes) {
  if (buffer.size() == bytes) return std::move(buffer);
  ByteBuffer shorter(bytes);
  if (bytes > 0) std::memcpy(shorter.data(), buffer.data(), bytes);
  return shorter;
}

}  // namespace

bool E57ChunkReader::next(PointCloud& chunk, std::size_t max_points) {
  State& s = *state_;
  const E57Header& header = s.header;
  const Quantization& q = s.quantization;
  // At most this many points: the records left (invalid ones are skipped, so maybe fewer).
  std::uint64_t records_left = 0;
  for (std::size_t scan = s.current_scan; scan < s.layouts.size(); ++scan) {
    const std::uint64_t in_scan = header.document.scans[scan].record_count;
    const std::uint64_t done = scan == s.current_scan && s.decoder ? s.scan_records_done : 0;
    records_left += std::min(in_scan, s.per_scan_limit) - std::min(done, in_scan);
  }
  const std::size_t capacity = std::size_t(std::min<std::uint64_t>(max_points, records_left));
  Column<Int3> positions(capacity);
  Column<Rgba8> colors(header.has_colors ? capacity : 0);
  Column<float> intensity(header.has_intensity ? capacity : 0);
  ByteBuffer scan_index(capacity * sizeof(std::uint32_t));
  std::vector<ScalarColumn> extra;
  for (const ExtraColumn& e : s.extras) {
    extra.push_back({e.name, e.type, ByteBuffer(capacity * scalarSize(e.type))});
  }
  // Quantizing with the inverse scale: a multiplication where Quantization divides, and the
  // range check folded in (the stored integer is the same: both round to nearest).
  double inverse[3], lowest[3], highest[3];
  for (int a = 0; a < 3; ++a) {
    inverse[a] = 1.0 / q.scale[a];
    lowest[a] = double(Quantization::kMin), highest[a] = double(Quantization::kMax);
  }
  std::size_t count = 0;
  std::vector<double> world[3];
  while (count < capacity) {
    const std::size_t want = std::min(kBatchRecords, capacity - count);
    const std::size_t n = s.decodeBatch(want, false);
    if (n == 0) break;
    const std::uint64_t first_record = s.scan_records_done - n;
    const ScanLayout& layout = s.layouts[s.current_scan];
    const E57Scan& scan = header.document.scans[s.current_scan];
    for (auto& w : world) w.resize(n);
    std::vector<std::uint8_t> valid(n);
    for (std::size_t i = 0; i < n; ++i) {
      double p[3] = {0.0, 0.0, 0.0};  // what position() leaves of an invalid point is not read
      valid[i] = s.position(layout, i, p);
      world[0][i] = p[0], world[1][i] = p[1], world[2][i] = p[2];
    }
    const std::size_t start = count;
    for (std::size_t i = 0; i < n; ++i) {
      if (!valid[i]) continue;
      std::int32_t quantized[3];
      for (int a = 0; a < 3; ++a) {
        const double value = (world[a][i] - q.offset[a]) * inverse[a];
        if (value >= lowest[a] && value <= highest[a]) {
          quantized[a] = std::int32_t(std::nearbyint(value));
          continue;
        }
        const std::string where = "record " + std::to_string(first_record + i) + " of scan " +
                                  std::to_string(s.current_scan);
        if (!std::isfinite(world[a][i])) {
          throw InputError({.file = s.pages->name(),
                            .byte_offset = scan.section_offset,
                            .element = where,
                            .property = scan.fields[std::size_t(layout.position[a])].name,
                            .expected = "a finite coordinate",
                            .found = std::to_string(world[a][i])});
        }
        throw OutsideDeclaredBounds(
            {.file = s.pages->name(),
             .byte_offset = scan.section_offset,
             .element = where,
             .property = "xyz"[a] + std::string(" in the file's frame"),
             .expected = "a point inside the bounds the file declares (" +
                         std::to_string(header.bounds.min[a]) + " .. " +
                         std::to_string(header.bounds.max[a]) + ")",
             .found = std::to_string(world[a][i]),
             .hint = "the file's cartesianBounds are wrong; readE57 measures them instead"});
      }
      positions[count++] = {quantized[0], quantized[1], quantized[2]};
    }
    std::fill_n(reinterpret_cast<std::uint32_t*>(scan_index.data()) + start, count - start,
                std::uint32_t(s.current_scan));
    if (header.has_colors) {
      const bool has = layout.color[0] >= 0;
      const double* channel[3] = {};
      if (has) {
        for (int k = 0; k < 3; ++k) channel[k] = s.values[std::size_t(layout.color[k])].data();
      }
      const double* invalid =
          layout.color_invalid >= 0 ? s.values[std::size_t(layout.color_invalid)].data() : nullptr;
      std::size_t out = start;
      for (std::size_t i = 0; i < n; ++i) {
        if (!valid[i]) continue;
        Rgba8 c{0, 0, 0, 255};
        if (has && !(invalid && invalid[i] != 0.0)) {
          std::uint8_t rgb[3];
          for (int k = 0; k < 3; ++k) {
            const Channel& m = layout.color_map[k];
            const double v = (channel[k][i] - m.minimum) * m.factor;
            rgb[k] = std::uint8_t(std::clamp(std::nearbyint(v), 0.0, 255.0));
          }
          c = {rgb[0], rgb[1], rgb[2], 255};
        }
        colors[out++] = c;
      }
    }
    if (header.has_intensity) {
      const double* values =
          layout.intensity >= 0 ? s.values[std::size_t(layout.intensity)].data() : nullptr;
      const double* invalid = layout.intensity_invalid >= 0
                                  ? s.values[std::size_t(layout.intensity_invalid)].data()
                                  : nullptr;
      const Channel& m = layout.intensity_map;
      std::size_t out = start;
      for (std::size_t i = 0; i < n; ++i) {
        if (!valid[i]) continue;
        float value = 0.0f;
        if (values && !(invalid && invalid[i] != 0.0)) {
          const double v = values[i];
          value = float(m.raw ? v : std::clamp((v - m.minimum) * m.factor, 0.0, 65535.0));
        }
        intensity[out++] = value;
      }
    }
    for (std::size_t e = 0; e < extra.size(); ++e) {
      int field = -1;
      for (const auto& [f, column] : layout.extras) {
        if (std::size_t(column) == e) field = f;
      }
      std::size_t out = start;
      for (std::size_t i = 0; i < n; ++i) {
        if (!valid[i]) continue;
        extra[e].setFromDouble(out++, field >= 0 ? s.values[std::size_t(field)][i] : 0.0);
      }
    }
  }
  chunk = PointCloud{};
  chunk.count = count;
  chunk.quantization = q;
  chunk.source.position = ScalarType::Float64;
  chunk.source.color = ScalarType::UInt8;
  for (const ScanLayout& layout : s.layouts) {
    for (const Channel& c : layout.color_map) {
      if (c.factor < 1.0 - 1e-12) chunk.source.color = ScalarType::UInt16;
    }
  }
  chunk.positions = cut(std::move(positions), count);
  if (header.has_colors) chunk.colors = cut(std::move(colors), count);
  if (header.has_intensity) chunk.intensity = cut(std::move(intensity), count);
  chunk.scalars.push_back(
      {column_names::kScanIndex, ScalarType::UInt32, cut(std::move(scan_index), count * 4)});
  for (ScalarColumn& column : extra) {
    column.data = cut(std::move(column.data), count * scalarSize(column.type));
    chunk.scalars.push_back(std::move(column));
  }
  chunk.computeBounds();
  return chunk.count > 0;
}

namespace {

PointCloud readAll(E57ChunkReader& reader) {
  PointCloud cloud;
  const std::uint64_t records = std::max<std::uint64_t>(reader.pointCount(), 1);
  reader.next(cloud, std::size_t(records));
  return cloud;
}

template <class Open>
PointCloud readWhole(Open open, const E57ReadOptions& options) {
  E57ChunkReader reader = open();
  reader.setProgress(options.progress);
  try {
    return readAll(reader);
  } catch (const OutsideDeclaredBounds&) {
    // The file's bounds are wrong: read it again with bounds measured from its points.
  }
  E57ChunkReader again = open();
  again.measureBounds();
  return readAll(again);
}

}  // namespace

PointCloud readE57(const std::filesystem::path& path, const E57ReadOptions& options) {
  return readWhole([&] { return E57ChunkReader(path); }, options);
}

PointCloud readE57FromMemory(std::span<const std::byte> bytes, const std::string& name,
                             const E57ReadOptions& options) {
  return readWhole([&] { return E57ChunkReader(bytes, name); }, options);
}

PointCloud readE57Preview(const std::filesystem::path& path, std::uint64_t max_points) {
  E57ChunkReader reader(path);
  const std::size_t scans = std::max<std::size_t>(reader.header().document.scans.size(), 1);
  reader.limitRecordsPerScan(std::max<std::uint64_t>(max_points / scans, 1));
  PointCloud cloud;
  reader.next(cloud, std::size_t(std::max<std::uint64_t>(max_points, 1)));
  return cloud;
}

}  // namespace parallax
