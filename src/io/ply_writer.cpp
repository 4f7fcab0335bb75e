// PLY output: a field list built once from the layout, then blocks of rows encoded into a large
// buffer and written with one fwrite each.
//
// Binary blocks are encoded a field at a time (one tight loop per property, strided stores into
// the row buffer) rather than a row at a time: the type dispatch happens once per field and block
// instead of once per value, which keeps a 27-byte-record file well above 1 GB/s of encoding.
// Ascii rows are printed value by value with std::to_chars, whose shortest form reads back to the
// same bits (the contract in ply_writer.h).
#include "io/ply_writer.h"

#include "core/color_depth.h"
#include "core/column_names.h"
#include "io/partial_output.h"

#include <atomic>
#include <bit>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>
#include <system_error>
#include <type_traits>
#include <vector>

namespace parallax {
namespace {

// Rows are encoded into blocks of about this size: large enough that fwrite and the kernel see
// few big requests, small enough to stay in L2/L3 while being filled.
constexpr std::size_t kBlockBytes = std::size_t{4} << 20;
// An ascii value takes at most 24 characters (a double's shortest form, a sign and a separator).
constexpr std::size_t kMaxAsciiValueChars = 32;

enum class FieldSource {
  PositionX,
  PositionY,
  PositionZ,
  Red,
  Green,
  Blue,
  Alpha,
  NormalX,
  NormalY,
  NormalZ,
  Intensity,
  Classification,
  Scalar,
};

struct Field {
  FieldSource source;
  ScalarType type;           // as written in the file
  std::size_t scalar_index;  // for FieldSource::Scalar
  std::string name;
};

ScalarType positionType(const SourceTypes& source) {
  return source.position == ScalarType::Float32 ? ScalarType::Float32 : ScalarType::Float64;
}

ScalarType colorType(const SourceTypes& source) {
  switch (source.color) {
    case ScalarType::UInt16:
    case ScalarType::Float32:
    case ScalarType::Float64:
      return source.color;
    default:
      return ScalarType::UInt8;  // the model holds 8 bits; other types add nothing
  }
}

// Every attribute's field, in the order `properties` asks (PointCloud::attributeOrder).
std::vector<Field> buildFields(const PointCloud& layout,
                               const std::vector<std::string>& properties) {
  std::vector<Field> fields;
  ScalarType position = positionType(layout.source);
  fields.push_back({FieldSource::PositionX, position, 0, column_names::kX});
  fields.push_back({FieldSource::PositionY, position, 0, column_names::kY});
  fields.push_back({FieldSource::PositionZ, position, 0, column_names::kZ});
  if (layout.hasColors()) {
    ScalarType color = colorType(layout.source);
    fields.push_back({FieldSource::Red, color, 0, column_names::kRed});
    fields.push_back({FieldSource::Green, color, 0, column_names::kGreen});
    fields.push_back({FieldSource::Blue, color, 0, column_names::kBlue});
    if (layout.source.has_alpha)
      fields.push_back({FieldSource::Alpha, color, 0, column_names::kAlpha});
  }
  if (layout.hasNormals()) {
    ScalarType normal =
        layout.source.normal == ScalarType::Float64 ? ScalarType::Float64 : ScalarType::Float32;
    fields.push_back({FieldSource::NormalX, normal, 0, column_names::kNx});
    fields.push_back({FieldSource::NormalY, normal, 0, column_names::kNy});
    fields.push_back({FieldSource::NormalZ, normal, 0, column_names::kNz});
  }
  if (layout.hasIntensity()) {
    fields.push_back(
        {FieldSource::Intensity, layout.source.intensity, 0, column_names::kIntensity});
  }
  if (layout.hasClassification()) {
    fields.push_back({FieldSource::Classification, layout.source.classification, 0,
                      column_names::kClassification});
  }
  for (std::size_t i = 0; i < layout.scalars.size(); ++i) {
    fields.push_back({FieldSource::Scalar, layout.scalars[i].type, i, layout.scalars[i].name});
  }
  std::vector<Field> ordered;
  for (const std::string& name : layout.attributeOrder(properties)) {
    for (const Field& field : fields) {
      if (field.name == name) {
        ordered.push_back(field);
        break;
      }
    }
  }
  return ordered;
}

// Calls f with a value of the C++ type that `type` names (the value itself is unused).
template <class F>
void withScalarType(ScalarType type, F&& f) {
  switch (type) {
    case ScalarType::Int8:
      return f(std::int8_t{});
    case ScalarType::UInt8:
      return f(std::uint8_t{});
    case ScalarType::Int16:
      return f(std::int16_t{});
    case ScalarType::UInt16:
      return f(std::uint16_t{});
    case ScalarType::Int32:
      return f(std::int32_t{});
    case ScalarType::UInt32:
      return f(std::uint32_t{});
    case ScalarType::Float32:
      return f(float{});
    case ScalarType::Float64:
      return f(double{});
  }
}

// Converts a value the model holds as floating point into the file's type: a plain cast for
// floating types, nearest and clamped for integers (an intensity read from a ushort is an exact
// integer in a float, so this gives it back unchanged).
template <class Out>
Out convertTo(double value) {
  if constexpr (std::is_floating_point_v<Out>) {
    return static_cast<Out>(value);
  } else {
    double rounded = std::nearbyint(value);
    if (!(rounded >= double(std::numeric_limits<Out>::min()))) {
      return std::numeric_limits<Out>::min();  // also NaN
    }
    if (rounded >= double(std::numeric_limits<Out>::max())) return std::numeric_limits<Out>::max();
    return static_cast<Out>(rounded);
  }
}

template <class T>
T byteSwapped(T value) {
  if constexpr (sizeof(T) == 1) {
    return value;
  } else if constexpr (sizeof(T) == 2) {
    return std::bit_cast<T>(__builtin_bswap16(std::bit_cast<std::uint16_t>(value)));
  } else if constexpr (sizeof(T) == 4) {
    return std::bit_cast<T>(__builtin_bswap32(std::bit_cast<std::uint32_t>(value)));
  } else {
    static_assert(sizeof(T) == 8);
    return std::bit_cast<T>(__builtin_bswap64(std::bit_cast<std::uint64_t>(value)));
  }
}

constexpr bool kHostIsLittleEndian = std::endian::native == std::endian::little;

// One field of `count` rows from `first`: out[i * stride] = get(first + i), in the file's byte
// order.
template <class Out, class Get>
void encodeField(std::byte* out, std::size_t stride, std::size_t first, std::size_t count,
                 bool swap, Get get) {
  for (std::size_t i = 0; i < count; ++i) {
    Out value = get(first + i);
    if (swap) value = byteSwapped(value);
    std::memcpy(out + i * stride, &value, sizeof(Out));
  }
}

// The value of field `field` for point `i` as the file's type Out (ascii and binary share this).
template <class Out>
struct FieldReader {
  const PointCloud& cloud;
  const Field& field;

  Out colorValue(std::uint8_t c) const {
    if constexpr (std::is_floating_point_v<Out>) {
      return Out(c) / Out(255);
    } else if constexpr (sizeof(Out) == 2) {
      return Out(colorTo16Bits(c));  // the full 16-bit range (core/color_depth.h)
    } else {
      return Out(c);
    }
  }

  Out operator()(std::size_t i) const {
    switch (field.source) {
      case FieldSource::PositionX:
        return convertTo<Out>(cloud.worldX(i));
      case FieldSource::PositionY:
        return convertTo<Out>(cloud.worldY(i));
      case FieldSource::PositionZ:
        return convertTo<Out>(cloud.worldZ(i));
      case FieldSource::Red:
        return colorValue(cloud.colors[i].r);
      case FieldSource::Green:
        return colorValue(cloud.colors[i].g);
      case FieldSource::Blue:
        return colorValue(cloud.colors[i].b);
      case FieldSource::Alpha:
        return colorValue(cloud.colors[i].a);
      case FieldSource::NormalX:
        return convertTo<Out>(cloud.normals[i].x);
      case FieldSource::NormalY:
        return convertTo<Out>(cloud.normals[i].y);
      case FieldSource::NormalZ:
        return convertTo<Out>(cloud.normals[i].z);
      case FieldSource::Intensity:
        return convertTo<Out>(cloud.intensity[i]);
      case FieldSource::Classification:
        return convertTo<Out>(cloud.classification[i]);
      case FieldSource::Scalar:
        return cloud.scalars[field.scalar_index].template as<Out>()[i];
    }
    return Out{};
  }
};

// Binary: one loop per field with the source chosen outside it (the hot path of the generator).
template <class Out>
void encodeBinaryField(const PointCloud& cloud, const Field& field, std::byte* out,
                       std::size_t stride, std::size_t first, std::size_t count, bool swap) {
  const auto& q = cloud.quantization;
  const Int3* p = cloud.positions.data();
  const Rgba8* c = cloud.colors.data();
  const Float3* n = cloud.normals.data();
  switch (field.source) {
    case FieldSource::PositionX:
      return encodeField<Out>(out, stride, first, count, swap,
                              [&](std::size_t i) { return convertTo<Out>(q.toWorld(0, p[i].x)); });
    case FieldSource::PositionY:
      return encodeField<Out>(out, stride, first, count, swap,
                              [&](std::size_t i) { return convertTo<Out>(q.toWorld(1, p[i].y)); });
    case FieldSource::PositionZ:
      return encodeField<Out>(out, stride, first, count, swap,
                              [&](std::size_t i) { return convertTo<Out>(q.toWorld(2, p[i].z)); });
    case FieldSource::NormalX:
      return encodeField<Out>(out, stride, first, count, swap,
                              [&](std::size_t i) { return Out(n[i].x); });
    case FieldSource::NormalY:
      return encodeField<Out>(out, stride, first, count, swap,
                              [&](std::size_t i) { return Out(n[i].y); });
    case FieldSource::NormalZ:
      return encodeField<Out>(out, stride, first, count, swap,
                              [&](std::size_t i) { return Out(n[i].z); });
    case FieldSource::Red:
      if constexpr (std::is_same_v<Out, std::uint8_t>) {
        return encodeField<Out>(out, stride, first, count, false,
                                [&](std::size_t i) { return c[i].r; });
      }
      break;
    case FieldSource::Green:
      if constexpr (std::is_same_v<Out, std::uint8_t>) {
        return encodeField<Out>(out, stride, first, count, false,
                                [&](std::size_t i) { return c[i].g; });
      }
      break;
    case FieldSource::Blue:
      if constexpr (std::is_same_v<Out, std::uint8_t>) {
        return encodeField<Out>(out, stride, first, count, false,
                                [&](std::size_t i) { return c[i].b; });
      }
      break;
    default:
      break;
  }
  encodeField<Out>(out, stride, first, count, swap, FieldReader<Out>{cloud, field});
}

template <class T>
char* printValue(char* out, T value) {
  // Shortest round-trip form for floating point; the buffer is sized by kMaxAsciiValueChars.
  return std::to_chars(out, out + kMaxAsciiValueChars, value).ptr;
}

char* printField(char* out, const PointCloud& cloud, const Field& field, std::size_t i) {
  withScalarType(field.type, [&](auto tag) {
    using Out = decltype(tag);
    Out value = FieldReader<Out>{cloud, field}(i);
    if constexpr (sizeof(Out) == 1) {
      out = printValue(out, int(value));  // to_chars of a char type would be a character
    } else {
      out = printValue(out, value);
    }
  });
  return out;
}

std::filesystem::path temporaryPathFor(const std::filesystem::path& path) {
  // Beside the target (same file system, so the final rename is atomic), hidden, and unique per
  // process and writer so that two writers of the same target never share a temporary
  // (partial_output.h: the next conversion removes it if this process is killed).
  return newPartialFilePath(path);
}

[[noreturn]] void throwSystemError(const std::string& what, const std::filesystem::path& path,
                                   int error) {
  throw std::runtime_error(what + " '" + path.string() + "': " + std::strerror(error));
}

bool sameLayout(const PointCloud& a, const PointCloud& b) {
  if (a.hasColors() != b.hasColors() || a.hasNormals() != b.hasNormals() ||
      a.hasIntensity() != b.hasIntensity() || a.hasClassification() != b.hasClassification()) {
    return false;
  }
  const SourceTypes& s = a.source;
  const SourceTypes& t = b.source;
  if (s.position != t.position || s.color != t.color || s.normal != t.normal ||
      s.intensity != t.intensity || s.classification != t.classification ||
      s.has_alpha != t.has_alpha || a.scalars.size() != b.scalars.size()) {
    return false;
  }
  for (std::size_t i = 0; i < a.scalars.size(); ++i) {
    if (a.scalars[i].name != b.scalars[i].name || a.scalars[i].type != b.scalars[i].type) {
      return false;
    }
  }
  return true;
}

bool columnsHaveCount(const PointCloud& cloud) {
  auto ok = [&](std::size_t size, bool present) { return !present || size == cloud.count; };
  if (cloud.positions.size() != cloud.count) return false;
  if (!ok(cloud.colors.size(), cloud.hasColors()) ||
      !ok(cloud.normals.size(), cloud.hasNormals()) ||
      !ok(cloud.intensity.size(), cloud.hasIntensity()) ||
      !ok(cloud.classification.size(), cloud.hasClassification())) {
    return false;
  }
  for (const auto& column : cloud.scalars) {
    if (column.data.size() != cloud.count * scalarSize(column.type)) return false;
  }
  return true;
}

}  // namespace

struct PlyStreamWriter::State {
  std::filesystem::path path;
  std::filesystem::path temp_path;
  std::FILE* file = nullptr;
  PointCloud layout;  // attributes only (no points): what every chunk must match
  std::vector<Field> fields;
  std::vector<std::size_t> offsets;  // of each field in a binary record
  std::size_t record_size = 0;
  std::uint64_t total_points = 0;
  std::uint64_t written = 0;
  PlyWriteOptions options;
  std::vector<char> buffer;
  bool finished = false;

  void writeBytes(const void* data, std::size_t size) {
    if (size != 0 && std::fwrite(data, 1, size, file) != size) {
      int error = errno;
      throwSystemError("cannot write", temp_path, error);
    }
  }

  void writeBinary(const PointCloud& chunk) {
    bool swap = (options.format == PlyFormat::BinaryBigEndian) == kHostIsLittleEndian;
    std::size_t rows_per_block = std::max<std::size_t>(1, kBlockBytes / record_size);
    for (std::size_t first = 0; first < chunk.count; first += rows_per_block) {
      std::size_t count = std::min<std::size_t>(rows_per_block, chunk.count - first);
      auto* out = reinterpret_cast<std::byte*>(buffer.data());
      for (std::size_t f = 0; f < fields.size(); ++f) {
        withScalarType(fields[f].type, [&](auto tag) {
          encodeBinaryField<decltype(tag)>(chunk, fields[f], out + offsets[f], record_size, first,
                                           count, swap);
        });
      }
      writeBytes(buffer.data(), count * record_size);
      if (options.progress) options.progress->advance(count);
    }
  }

  void writeAscii(const PointCloud& chunk) {
    std::size_t row_limit = fields.size() * kMaxAsciiValueChars + 1;
    char* begin = buffer.data();
    char* end = begin + buffer.size();
    char* out = begin;
    std::uint64_t pending = 0;
    for (std::size_t i = 0; i < chunk.count; ++i) {
      if (std::size_t(end - out) < row_limit) {
        writeBytes(begin, std::size_t(out - begin));
        out = begin;
        if (options.progress) options.progress->advance(pending);
        pending = 0;
      }
      for (std::size_t f = 0; f < fields.size(); ++f) {
        if (f != 0) *out++ = ' ';
        out = printField(out, chunk, fields[f], i);
      }
      *out++ = '\n';
      ++pending;
    }
    writeBytes(begin, std::size_t(out - begin));
    if (options.progress) options.progress->advance(pending);
  }
};

PlyStreamWriter::PlyStreamWriter(const std::filesystem::path& path, const PointCloud& layout,
                                 std::uint64_t total_points, const PlyWriteOptions& options)
    : state_(std::make_unique<State>()) {
  State& s = *state_;
  s.path = path;
  s.temp_path = temporaryPathFor(path);
  s.total_points = total_points;
  s.options = options;
  s.fields = buildFields(layout, options.properties);
  for (const auto& field : s.fields) {
    s.offsets.push_back(s.record_size);
    s.record_size += scalarSize(field.type);
  }
  // Keep the layout's attributes but none of its points: chunks are checked against it.
  s.layout.source = layout.source;
  s.layout.colors = Column<Rgba8>(layout.hasColors() ? 1 : 0);
  s.layout.normals = Column<Float3>(layout.hasNormals() ? 1 : 0);
  s.layout.intensity = Column<float>(layout.hasIntensity() ? 1 : 0);
  s.layout.classification = Column<std::uint8_t>(layout.hasClassification() ? 1 : 0);
  for (const auto& column : layout.scalars) s.layout.scalars.push_back({column.name, column.type});
  s.buffer.resize(std::max(kBlockBytes, s.fields.size() * kMaxAsciiValueChars + 1));

  PlyHeader header;
  header.format = options.format;
  header.comments.push_back("generated by Parallax");
  if (positionType(layout.source) == ScalarType::Float64 && options.format != PlyFormat::Ascii) {
    // The grid the doubles lie on, for our reader (ply_header.h, kPlyQuantizationComment).
    std::string comment(kPlyQuantizationComment);
    for (const auto* values : {&layout.quantization.scale, &layout.quantization.offset}) {
      for (double v : *values) {
        char digits[32];
        comment += ' ';
        comment.append(digits, std::to_chars(digits, digits + sizeof digits, v).ptr);
      }
    }
    header.comments.push_back(std::move(comment));
  }
  header.comments.insert(header.comments.end(), options.comments.begin(), options.comments.end());
  PlyElement vertex;
  vertex.name = "vertex";
  vertex.count = total_points;
  for (const auto& field : s.fields) vertex.properties.push_back({field.name, field.type});
  header.elements.push_back(std::move(vertex));
  std::string text = formatPlyHeader(header);

  s.file = std::fopen(s.temp_path.c_str(), "wb");
  if (s.file == nullptr) {
    int error = errno;  // before any allocation below can touch it
    throwSystemError("cannot write '" + path.string() + "': cannot create the temporary file",
                     s.temp_path, error);
  }
  // Our writes are already large blocks; stdio's own buffer would only add a copy.
  std::setvbuf(s.file, nullptr, _IONBF, 0);
  try {
    s.writeBytes(text.data(), text.size());
  } catch (...) {
    std::fclose(s.file);
    std::remove(s.temp_path.c_str());
    throw;
  }
}

PlyStreamWriter::~PlyStreamWriter() {
  if (!state_ || state_->finished) return;
  if (state_->file != nullptr) std::fclose(state_->file);
  std::error_code ignored;
  std::filesystem::remove(state_->temp_path, ignored);
}

void PlyStreamWriter::write(const PointCloud& chunk) {
  State& s = *state_;
  if (s.finished) throw std::logic_error("PlyStreamWriter::write called after finish()");
  if (!sameLayout(chunk, s.layout)) {
    throw std::logic_error("PlyStreamWriter::write: the chunk's attributes differ from the layout");
  }
  if (!columnsHaveCount(chunk)) {
    throw std::logic_error("PlyStreamWriter::write: a column's size differs from chunk.count");
  }
  if (s.written + chunk.count > s.total_points) {
    throw std::runtime_error(
        "writing '" + s.path.string() + "': " + std::to_string(s.written + chunk.count) +
        " points given, but the " + "header announces " + std::to_string(s.total_points));
  }
  if (s.options.format == PlyFormat::Ascii) {
    s.writeAscii(chunk);
  } else {
    s.writeBinary(chunk);
  }
  s.written += chunk.count;
}

void PlyStreamWriter::finish() {
  State& s = *state_;
  if (s.finished) return;
  if (s.written != s.total_points) {
    throw std::runtime_error("writing '" + s.path.string() + "': " + std::to_string(s.written) +
                             " points written, but the header announces " +
                             std::to_string(s.total_points) + "; the file was not created");
  }
  std::FILE* file = std::exchange(s.file, nullptr);
  if (std::fclose(file) != 0) {
    int error = errno;
    throwSystemError("cannot write", s.temp_path, error);
  }
  std::error_code error;
  std::filesystem::rename(s.temp_path, s.path, error);
  if (error) {
    throw std::runtime_error("cannot rename '" + s.temp_path.string() + "' to '" + s.path.string() +
                             "': " + error.message());
  }
  s.finished = true;
}

void writePly(const PointCloud& cloud, const std::filesystem::path& path,
              const PlyWriteOptions& options) {
  PlyStreamWriter writer(path, cloud, cloud.count, options);
  writer.write(cloud);
  writer.finish();
}

}  // namespace parallax
