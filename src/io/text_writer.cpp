#include "io/text_writer.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "core/column_names.h"
#include "io/point_file.h"

namespace parallax {
namespace {

// The decimals that print every value offset + k * scale exactly: d when `scale` is 10^-d
// (d = 0..9) and `offset` has at most d decimals, else the offset's own decimals up to 9 (a LAS
// offset such as 2014969.123479 under a scale of 1e-5: five decimals would move the point by up
// to 5e-6); none (the shortest digits that read back to the same double) when the scale is no
// power of ten or the offset needs more than 9 decimals.
std::optional<int> decimalsOf(double scale, double offset) {
  double p = 1.0;
  for (int d = 0; d <= 9; ++d, p *= 10.0) {
    if (std::abs(scale * p - 1.0) >= 1e-9) continue;
    for (int e = d; e <= 9; ++e) {
      // The offset printed with e decimals reads back as itself: it has at most e decimals.
      char buffer[64];
      auto printed =
          std::to_chars(buffer, buffer + sizeof buffer, offset, std::chars_format::fixed, e);
      if (printed.ec != std::errc()) return std::nullopt;  // |offset| too large for fixed digits
      double back = 0;
      std::from_chars(buffer, printed.ptr, back);
      if (back == offset) return e;
    }
    return std::nullopt;
  }
  return std::nullopt;
}

template <class T>
void append(std::string& out, T value) {
  char buffer[64];
  auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  out.append(buffer, result.ptr);
}

void appendFixed(std::string& out, double value, int decimals) {
  char buffer[64];
  auto result =
      std::to_chars(buffer, buffer + sizeof buffer, value, std::chars_format::fixed, decimals);
  out.append(buffer, result.ptr);
}

void appendScalar(std::string& out, const ScalarColumn& column, std::size_t i) {
  switch (column.type) {
    case ScalarType::Int8:
      append(out, int(column.as<std::int8_t>()[i]));
      break;
    case ScalarType::UInt8:
      append(out, unsigned(column.as<std::uint8_t>()[i]));
      break;
    case ScalarType::Int16:
      append(out, column.as<std::int16_t>()[i]);
      break;
    case ScalarType::UInt16:
      append(out, column.as<std::uint16_t>()[i]);
      break;
    case ScalarType::Int32:
      append(out, column.as<std::int32_t>()[i]);
      break;
    case ScalarType::UInt32:
      append(out, column.as<std::uint32_t>()[i]);
      break;
    case ScalarType::Float32:
      append(out, column.as<float>()[i]);
      break;
    case ScalarType::Float64:
      append(out, column.as<double>()[i]);
      break;
  }
}

// One written column: which attribute, and for a scalar which column.
enum class Field {
  X,
  Y,
  Z,
  Red,
  Green,
  Blue,
  Alpha,
  Nx,
  Ny,
  Nz,
  Intensity,
  Classification,
  Scalar
};

struct WrittenColumn {
  Field field;
  std::size_t scalar = 0;
};

struct Plan {
  char delimiter;
  std::optional<int> decimals[3];
  std::vector<WrittenColumn> columns;
  std::vector<std::string> names;  // the header line's
};

WrittenColumn columnFor(const PointCloud& cloud, const std::string& name) {
  static const std::pair<const char*, Field> kNames[] = {
      {column_names::kX, Field::X},
      {column_names::kY, Field::Y},
      {column_names::kZ, Field::Z},
      {column_names::kRed, Field::Red},
      {column_names::kGreen, Field::Green},
      {column_names::kBlue, Field::Blue},
      {column_names::kAlpha, Field::Alpha},
      {column_names::kNx, Field::Nx},
      {column_names::kNy, Field::Ny},
      {column_names::kNz, Field::Nz},
      {column_names::kIntensity, Field::Intensity},
      {column_names::kClassification, Field::Classification}};
  for (std::size_t i = 0; i < cloud.scalars.size(); ++i) {
    if (cloud.scalars[i].name == name) return {Field::Scalar, i};
  }
  for (const auto& [text, field] : kNames) {
    if (name == text) return {field, 0};
  }
  return {Field::Scalar, 0};  // cannot happen: names come from attributeOrder
}

void formatBlock(const PointCloud& cloud, const Plan& plan, std::size_t first, std::size_t n,
                 std::string& out) {
  out.clear();
  const char sep = plan.delimiter;
  for (std::size_t i = first; i < first + n; ++i) {
    bool first_column = true;
    for (const WrittenColumn& column : plan.columns) {
      if (!first_column) out += sep;
      first_column = false;
      switch (column.field) {
        case Field::X:
        case Field::Y:
        case Field::Z: {
          const int axis = int(column.field) - int(Field::X);
          const Int3& p = cloud.positions[i];
          const std::int32_t q = axis == 0 ? p.x : axis == 1 ? p.y : p.z;
          const double world = cloud.quantization.toWorld(axis, q);
          if (plan.decimals[axis]) {
            appendFixed(out, world, *plan.decimals[axis]);
          } else {
            append(out, world);
          }
          break;
        }
        case Field::Red:
          append(out, unsigned(cloud.colors[i].r));
          break;
        case Field::Green:
          append(out, unsigned(cloud.colors[i].g));
          break;
        case Field::Blue:
          append(out, unsigned(cloud.colors[i].b));
          break;
        case Field::Alpha:
          append(out, unsigned(cloud.colors[i].a));
          break;
        case Field::Nx:
          append(out, cloud.normals[i].x);
          break;
        case Field::Ny:
          append(out, cloud.normals[i].y);
          break;
        case Field::Nz:
          append(out, cloud.normals[i].z);
          break;
        case Field::Intensity:
          append(out, cloud.intensity[i]);
          break;
        case Field::Classification:
          append(out, unsigned(cloud.classification[i]));
          break;
        case Field::Scalar:
          appendScalar(out, cloud.scalars[column.scalar], i);
          break;
      }
    }
    out += '\n';
  }
}

// The layouts text_layout.cpp's commonLayout gives a file of 3, 4, 6, 7 or 9 columns without
// names, under the names this writer prints.
bool isLayoutReadByCount(const std::vector<std::string>& names) {
  using namespace column_names;
  static const std::vector<std::vector<std::string>> kLayouts = {
      {kX, kY, kZ},
      {kX, kY, kZ, kIntensity},
      {kX, kY, kZ, kRed, kGreen, kBlue},
      {kX, kY, kZ, kIntensity, kRed, kGreen, kBlue},
      {kX, kY, kZ, kRed, kGreen, kBlue, kNx, kNy, kNz}};
  return std::find(kLayouts.begin(), kLayouts.end(), names) != kLayouts.end();
}

}  // namespace

TextWriteOptions textOptionsForPath(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  TextWriteOptions options;
  if (ext == ".csv") options.delimiter = ',';
  if (ext == ".pts") options.pts = true;
  if (ext == ".xyz") options.header_only_when_needed = true;
  return options;
}

std::vector<std::string> describeTextLosses(const PointCloud& cloud,
                                            const TextWriteOptions& options) {
  std::vector<std::string> losses;
  if (!options.pts) return losses;
  if (cloud.source.has_alpha) losses.push_back("alpha (PTS has none)");
  if (cloud.hasNormals()) losses.push_back("normals (PTS has none)");
  if (cloud.hasClassification()) losses.push_back("classification (PTS has none)");
  for (const ScalarColumn& column : cloud.scalars) {
    losses.push_back(column.name + " (PTS has only x y z intensity r g b)");
  }
  return losses;
}

struct TextStreamWriter::State {
  Plan plan;
  OutputFile out;
  std::uint64_t count = 0, written = 0;
  Progress* progress = nullptr;
  std::vector<std::string> buffers;
  explicit State(const std::filesystem::path& path) : out(path) {}
};

TextStreamWriter::TextStreamWriter(const std::filesystem::path& path, const PointCloud& layout,
                                   std::uint64_t count, const TextWriteOptions& options)
    : state_(std::make_unique<State>(path)) {
  Plan& plan = state_->plan;
  plan.delimiter = options.pts ? ' ' : options.delimiter;
  for (int axis = 0; axis < 3; ++axis)
    plan.decimals[axis] = decimalsOf(layout.quantization.scale[std::size_t(axis)],
                                     layout.quantization.offset[std::size_t(axis)]);
  if (options.pts) {
    // PTS: x y z [intensity] [r g b], whatever the order asked.
    if (!options.properties.empty()) {
      throw std::invalid_argument(
          "PTS has a fixed layout (x y z intensity r g b): no order to "
          "choose");
    }
    plan.names = {column_names::kX, column_names::kY, column_names::kZ};
    if (layout.hasIntensity()) plan.names.push_back(column_names::kIntensity);
    if (layout.hasColors())
      plan.names.insert(plan.names.end(),
                        {column_names::kRed, column_names::kGreen, column_names::kBlue});
  } else {
    plan.names = layout.attributeOrder(options.properties);
  }
  for (const std::string& name : plan.names) plan.columns.push_back(columnFor(layout, name));
  state_->count = count;
  state_->progress = options.progress;
  if (options.pts) {
    state_->out.write(std::to_string(count) + "\n");
  } else if (options.header &&
             !(options.header_only_when_needed && isLayoutReadByCount(plan.names))) {
    std::string line;
    for (std::size_t i = 0; i < plan.names.size(); ++i) {
      if (i) line += plan.delimiter;
      line += plan.names[i];
    }
    state_->out.write(line + "\n");
  }
}

TextStreamWriter::~TextStreamWriter() = default;

void TextStreamWriter::write(const PointCloud& cloud) {
  // Blocks of lines formatted on every core, written in order: a batch's lines at a time.
  constexpr std::size_t kBlock = 1 << 15;
  constexpr std::size_t kBatch = 16;
  std::vector<std::string>& buffers = state_->buffers;
  buffers.resize(kBatch);
  const std::size_t count = cloud.count;
  for (std::size_t batch = 0; batch < count; batch += kBlock * kBatch) {
    std::size_t blocks = std::min(kBatch, (count - batch + kBlock - 1) / kBlock);
    tbb::parallel_for(std::size_t(0), blocks, [&](std::size_t b) {
      std::size_t first = batch + b * kBlock;
      formatBlock(cloud, state_->plan, first, std::min(kBlock, count - first), buffers[b]);
    });
    for (std::size_t b = 0; b < blocks; ++b) state_->out.write(buffers[b]);
    if (state_->progress) state_->progress->advance(std::min(count - batch, kBlock * kBatch));
  }
  state_->written += count;
}

void TextStreamWriter::finish() {
  if (state_->written != state_->count) {
    throw std::logic_error("TextStreamWriter: " + std::to_string(state_->written) +
                           " points written where " + std::to_string(state_->count) +
                           " were announced");
  }
  state_->out.commit();
}

void writeText(const PointCloud& cloud, const std::filesystem::path& path,
               const TextWriteOptions& options) {
  TextStreamWriter writer(path, cloud, cloud.count, options);
  writer.write(cloud);
  writer.finish();
}

}  // namespace parallax
