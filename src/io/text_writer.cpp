#include "io/text_writer.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <optional>

#include "io/point_file.h"

namespace parallax {
namespace {

// d when `scale` is 10^-d (d = 0..9), the decimals that print a quantized value exactly.
std::optional<int> decimalsOf(double scale) {
  double p = 1.0;
  for (int d = 0; d <= 9; ++d, p *= 10.0) {
    if (std::abs(scale * p - 1.0) < 1e-9) return d;
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

struct Plan {
  char delimiter;
  bool pts;
  std::optional<int> decimals[3];
  bool colors, alpha, normals, intensity, classification, scalars;
};

void formatBlock(const PointCloud& cloud, const Plan& plan, std::size_t first, std::size_t n,
                 std::string& out) {
  out.clear();
  const char sep = plan.delimiter;
  for (std::size_t i = first; i < first + n; ++i) {
    const Int3& p = cloud.positions[i];
    const std::int32_t q[3] = {p.x, p.y, p.z};
    for (int axis = 0; axis < 3; ++axis) {
      if (axis) out += sep;
      double world = cloud.quantization.toWorld(axis, q[axis]);
      if (plan.decimals[axis]) {
        appendFixed(out, world, *plan.decimals[axis]);
      } else {
        append(out, world);
      }
    }
    if (plan.intensity && plan.pts) {
      out += sep;
      append(out, cloud.intensity[i]);
    }
    if (plan.colors) {
      const Rgba8& c = cloud.colors[i];
      out += sep, append(out, unsigned(c.r));
      out += sep, append(out, unsigned(c.g));
      out += sep, append(out, unsigned(c.b));
      if (plan.alpha) out += sep, append(out, unsigned(c.a));
    }
    if (!plan.pts) {
      if (plan.normals) {
        const Float3& v = cloud.normals[i];
        out += sep, append(out, v.x);
        out += sep, append(out, v.y);
        out += sep, append(out, v.z);
      }
      if (plan.intensity) out += sep, append(out, cloud.intensity[i]);
      if (plan.classification) out += sep, append(out, unsigned(cloud.classification[i]));
      for (const ScalarColumn& column : cloud.scalars) {
        out += sep;
        appendScalar(out, column, i);
      }
    }
    out += '\n';
  }
}

}  // namespace

TextWriteOptions textOptionsForPath(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  TextWriteOptions options;
  if (ext == ".csv") options.delimiter = ',';
  if (ext == ".pts") options.pts = true;
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

void writeText(const PointCloud& cloud, const std::filesystem::path& path,
               const TextWriteOptions& options) {
  Plan plan{};
  plan.pts = options.pts;
  plan.delimiter = options.pts ? ' ' : options.delimiter;
  for (int axis = 0; axis < 3; ++axis)
    plan.decimals[axis] = decimalsOf(cloud.quantization.scale[std::size_t(axis)]);
  plan.colors = cloud.hasColors();
  plan.alpha = cloud.hasColors() && cloud.source.has_alpha && !options.pts;
  plan.normals = cloud.hasNormals();
  plan.intensity = cloud.hasIntensity();
  plan.classification = cloud.hasClassification();

  OutputFile out(path);
  if (options.pts) {
    out.write(std::to_string(cloud.count) + "\n");
  } else if (options.header) {
    std::vector<std::string> names = cloud.attributeNames();
    std::string line;
    for (std::size_t i = 0; i < names.size(); ++i) {
      if (i) line += plan.delimiter;
      line += names[i];
    }
    out.write(line + "\n");
  }
  constexpr std::size_t kBlock = 1 << 15;
  constexpr std::size_t kBatch = 16;
  std::vector<std::string> buffers(kBatch);
  const std::size_t count = cloud.count;
  for (std::size_t batch = 0; batch < count; batch += kBlock * kBatch) {
    std::size_t blocks = std::min(kBatch, (count - batch + kBlock - 1) / kBlock);
    tbb::parallel_for(std::size_t(0), blocks, [&](std::size_t b) {
      std::size_t first = batch + b * kBlock;
      formatBlock(cloud, plan, first, std::min(kBlock, count - first), buffers[b]);
    });
    for (std::size_t b = 0; b < blocks; ++b) out.write(buffers[b]);
    if (options.progress) options.progress->advance(std::min(count - batch, kBlock * kBatch));
  }
  out.commit();
}

}  // namespace parallax
