#include "io/pcd_writer.h"

#include <liblzf/lzf.h>

#include <charconv>
#include <cstring>
#include <stdexcept>

#include "core/column_names.h"
#include "io/point_file.h"

namespace parallax {
namespace {

// One field of the output and how to get point i's value of it.
struct OutField {
  PcdField field;
  enum class Source { X, Y, Z, Color, Nx, Ny, Nz, Intensity, Classification, Scalar } source;
  const ScalarColumn* scalar = nullptr;
};

PcdField fieldOfType(const std::string& name, ScalarType type) {
  switch (type) {
    case ScalarType::Int8:
      return {name, 'I', 1};
    case ScalarType::UInt8:
      return {name, 'U', 1};
    case ScalarType::Int16:
      return {name, 'I', 2};
    case ScalarType::UInt16:
      return {name, 'U', 2};
    case ScalarType::Int32:
      return {name, 'I', 4};
    case ScalarType::UInt32:
      return {name, 'U', 4};
    case ScalarType::Float32:
      return {name, 'F', 4};
    case ScalarType::Float64:
      break;
  }
  return {name, 'F', 8};
}

std::vector<OutField> planFields(const PointCloud& cloud, const std::vector<std::string>& chosen,
                                 PcdData data) {
  std::vector<OutField> fields;
  const bool float_positions = cloud.source.position == ScalarType::Float32;
  bool color_done = false;
  for (const std::string& name : cloud.attributeOrder(chosen)) {
    using S = OutField::Source;
    if (name == column_names::kX || name == column_names::kY || name == column_names::kZ) {
      fields.push_back({{name, 'F', float_positions ? 4u : 8u},
                        name == column_names::kX   ? S::X
                        : name == column_names::kY ? S::Y
                                                   : S::Z});
    } else if (name == column_names::kRed || name == column_names::kGreen ||
               name == column_names::kBlue || name == column_names::kAlpha) {
      if (color_done) continue;  // one packed field for the four channels
      color_done = true;
      // rgb as PCL's PointXYZRGB declares it, a float holding the bits (pcl_pcd2ply mis-writes
      // a U-typed rgb: 4 bytes under 3 uchar properties); in ascii an unsigned integer, as PCL
      // writes it (a float's digits would not keep its bits). rgba is uint32 in PCL too.
      const bool as_float = !cloud.source.has_alpha && data != PcdData::Ascii;
      fields.push_back(
          {{cloud.source.has_alpha ? "rgba" : "rgb", as_float ? 'F' : 'U', 4}, S::Color});
    } else if (name == column_names::kNx || name == column_names::kNy ||
               name == column_names::kNz) {
      fields.push_back({{"normal_" + name.substr(1), 'F', 4},
                        name == column_names::kNx   ? S::Nx
                        : name == column_names::kNy ? S::Ny
                                                    : S::Nz});
    } else if (name == column_names::kIntensity) {
      fields.push_back({{name, 'F', 4}, S::Intensity});
    } else if (name == column_names::kClassification) {
      fields.push_back({{name, 'U', 1}, S::Classification});
    } else {
      const ScalarColumn* column = cloud.findScalar(name);
      fields.push_back({fieldOfType(name, column->type), S::Scalar, column});
    }
  }
  std::uint32_t offset = 0;
  for (OutField& f : fields) {
    f.field.offset = offset;
    offset += f.field.size;
  }
  return fields;
}

// Point i's value of `f`, as the bytes of its type (`out` holds at least 8).
void valueBytes(const PointCloud& cloud, const OutField& f, std::size_t i, std::byte* out) {
  using S = OutField::Source;
  auto put = [&](auto value) { std::memcpy(out, &value, sizeof value); };
  switch (f.source) {
    case S::X:
    case S::Y:
    case S::Z: {
      const double world = f.source == S::X   ? cloud.worldX(i)
                           : f.source == S::Y ? cloud.worldY(i)
                                              : cloud.worldZ(i);
      if (f.field.size == 4) {
        put(float(world));
      } else {
        put(world);
      }
      return;
    }
    case S::Color: {
      const Rgba8 c = cloud.colors[i];
      const std::uint8_t a = cloud.source.has_alpha ? c.a : 0;
      put(std::uint32_t(a) << 24 | std::uint32_t(c.r) << 16 | std::uint32_t(c.g) << 8 | c.b);
      return;
    }
    case S::Nx:
      return put(cloud.normals[i].x);
    case S::Ny:
      return put(cloud.normals[i].y);
    case S::Nz:
      return put(cloud.normals[i].z);
    case S::Intensity:
      return put(cloud.intensity[i]);
    case S::Classification:
      return put(cloud.classification[i]);
    case S::Scalar:
      std::memcpy(out, f.scalar->data.data() + i * f.field.size, f.field.size);
      return;
  }
}

void appendAscii(std::string& line, const OutField& f, const std::byte* bytes) {
  char buffer[64];
  std::to_chars_result result{};
  auto print = [&](auto value) { result = std::to_chars(buffer, buffer + sizeof buffer, value); };
  auto as = [&](auto tag) {
    decltype(tag) value;
    std::memcpy(&value, bytes, sizeof value);
    return value;
  };
  const PcdField& field = f.field;
  if (field.type == 'F') {
    if (field.size == 4) {
      print(as(float{}));
    } else {
      print(as(double{}));
    }
  } else if (field.type == 'U') {
    if (field.size == 1) print(unsigned(as(std::uint8_t{})));
    if (field.size == 2) print(unsigned(as(std::uint16_t{})));
    if (field.size == 4) print(as(std::uint32_t{}));
  } else {
    if (field.size == 1) print(int(as(std::int8_t{})));
    if (field.size == 2) print(int(as(std::int16_t{})));
    if (field.size == 4) print(as(std::int32_t{}));
  }
  line.append(buffer, result.ptr);
}

}  // namespace

void writePcd(const PointCloud& cloud, const std::filesystem::path& path,
              const PcdWriteOptions& options) {
  const std::vector<OutField> fields = planFields(cloud, options.properties, options.data);
  PcdHeader header;
  for (const OutField& f : fields) header.fields.push_back(f.field);
  header.width = cloud.count;
  header.height = 1;
  header.points = cloud.count;
  header.viewpoint = options.viewpoint;
  header.data = options.data;
  std::uint32_t record_size = 0;
  for (const OutField& f : fields) record_size += f.field.size;
  const std::uint64_t data_size = cloud.count * record_size;
  if (options.data == PcdData::BinaryCompressed && data_size > 0xFFFFFFFFull) {
    throw std::invalid_argument(path.string() + ": binary_compressed PCD holds at most 4 GiB (" +
                                std::to_string(data_size) +
                                " bytes here); write binary PCD instead");
  }

  OutputFile out(path);
  out.write(formatPcdHeader(header));
  constexpr std::size_t kBlock = 1 << 16;
  std::byte value[8];
  if (options.data == PcdData::Ascii) {
    std::string text;
    for (std::size_t begin = 0; begin < cloud.count; begin += kBlock) {
      const std::size_t end = std::min<std::size_t>(cloud.count, begin + kBlock);
      text.clear();
      for (std::size_t i = begin; i < end; ++i) {
        for (std::size_t k = 0; k < fields.size(); ++k) {
          if (k != 0) text.push_back(' ');
          valueBytes(cloud, fields[k], i, value);
          appendAscii(text, fields[k], value);
        }
        text.push_back('\n');
      }
      out.write(text);
      if (options.progress) options.progress->advance(end - begin);
    }
  } else if (options.data == PcdData::Binary) {
    std::vector<std::byte> block(kBlock * record_size);
    for (std::size_t begin = 0; begin < cloud.count; begin += kBlock) {
      const std::size_t end = std::min<std::size_t>(cloud.count, begin + kBlock);
      std::byte* p = block.data();
      for (std::size_t i = begin; i < end; ++i) {
        for (const OutField& f : fields) {
          valueBytes(cloud, f, i, p);
          p += f.field.size;
        }
      }
      out.write(block.data(), std::size_t(p - block.data()));
      if (options.progress) options.progress->advance(end - begin);
    }
  } else {
    // Structure of arrays: every point's value of the first field, then of the second, ...
    std::vector<std::byte> plain(data_size);
    std::byte* p = plain.data();
    for (const OutField& f : fields) {
      for (std::size_t i = 0; i < cloud.count; ++i, p += f.field.size) valueBytes(cloud, f, i, p);
    }
    // LZF may expand incompressible data a little (one control byte every 32 literals).
    std::vector<std::byte> packed(data_size + data_size / 16 + 64);
    std::uint32_t sizes[2] = {0, std::uint32_t(data_size)};
    if (data_size > 0) {
      sizes[0] =
          lzf_compress(plain.data(), unsigned(data_size), packed.data(), unsigned(packed.size()));
      if (sizes[0] == 0) throw std::runtime_error(path.string() + ": LZF compression failed");
    }
    out.write(sizes, sizeof sizes);
    out.write(packed.data(), sizes[0]);
    if (options.progress) options.progress->advance(cloud.count);
  }
  out.commit();
}

}  // namespace parallax
