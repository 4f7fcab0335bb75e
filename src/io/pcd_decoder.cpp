#include "io/pcd_decoder.h"

#include <fast_float/fast_float.h>
#include <liblzf/lzf.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>

#include "core/byte_order.h"
#include "core/color_depth.h"
#include "core/column_names.h"
#include "core/error.h"
#include "io/las_field_names.h"
#include "io/ply_decoder.h"  // quantizeClamped

namespace parallax::pcd {
namespace {

// 'text', quoted for a message, with what a terminal should not see escaped.
std::string quoted(std::string_view text) {
  return quoteInput(text);
}

std::string lower(std::string_view name) {
  std::string out(name);
  std::transform(out.begin(), out.end(), out.begin(),
                 [](unsigned char c) { return char(std::tolower(c)); });
  return out;
}

ScalarType scalarTypeOf(char type, std::uint32_t size) {
  if (type == 'F') return size == 4 ? ScalarType::Float32 : ScalarType::Float64;
  const bool is_signed = type == 'I';
  switch (size) {
    case 1:
      return is_signed ? ScalarType::Int8 : ScalarType::UInt8;
    case 2:
      return is_signed ? ScalarType::Int16 : ScalarType::UInt16;
    case 4:
      return is_signed ? ScalarType::Int32 : ScalarType::UInt32;
    default:
      return ScalarType::Float64;  // 64-bit integers: the model has no such type
  }
}

// Calls f(T{}) with the C++ type of a PCD value, so that loops are typed before they start.
template <class F>
void dispatch(char type, std::uint32_t size, F&& f) {
  if (type == 'F') {
    if (size == 4) return f(float{});
    return f(double{});
  }
  if (type == 'I') {
    if (size == 1) return f(std::int8_t{});
    if (size == 2) return f(std::int16_t{});
    if (size == 4) return f(std::int32_t{});
    return f(std::int64_t{});
  }
  if (size == 1) return f(std::uint8_t{});
  if (size == 2) return f(std::uint16_t{});
  if (size == 4) return f(std::uint32_t{});
  return f(std::uint64_t{});
}

[[noreturn]] void failField(const std::string& file, const std::string& field,
                            const std::string& expected, const std::string& found) {
  throw InputError(
      {.file = file, .element = "header", .property = field, .expected = expected, .found = found});
}

}  // namespace

Layout mapFields(const PcdHeader& header, const std::string& file) {
  Layout layout;
  int normal_fields = 0;
  for (const char* n : {"normal_x", "normal_y", "normal_z"}) normal_fields += header.find(n) >= 0;
  const bool normals = normal_fields == 3;
  bool has[3] = {false, false, false};
  // Colour channels in three fields, where no packed rgb/rgba field gives the colour.
  int channels = 0;
  bool packed = false;
  for (const PcdField& field : header.fields) {
    const std::string name = lower(field.name);
    packed |= (name == "rgb" || name == "rgba") && field.count == 1 && field.size == 4;
    channels += (name == "red" || name == "green" || name == "blue") && field.count == 1;
  }
  const bool channel_colors = channels == 3 && !packed;
  for (std::size_t f = 0; f < header.fields.size(); ++f) {
    const PcdField& field = header.fields[f];
    const std::string name = lower(field.name);
    for (std::uint32_t i = 0; i < field.count; ++i) {
      Component c{.field = f, .index = i, .type = field.type, .size = field.size};
      c.name = field.count == 1 ? field.name : field.name + "_" + std::to_string(i);
      const bool single = field.count == 1;
      auto needSingle = [&](const char* what) {
        if (!single) {
          failField(file, field.name, std::string("COUNT 1 for ") + what,
                    "COUNT " + std::to_string(field.count));
        }
      };
      if (name == "x" || name == "y" || name == "z") {
        needSingle("a coordinate");
        const int axis = name[0] - 'x';
        if (has[axis]) failField(file, field.name, "one field of this name", "two");
        has[axis] = true;
        c.target = axis == 0 ? Target::X : axis == 1 ? Target::Y : Target::Z;
        (axis == 0 ? layout.x : axis == 1 ? layout.y : layout.z) = layout.components.size();
        layout.source.position = scalarTypeOf(field.type, field.size);
      } else if ((name == "rgb" || name == "rgba") && !layout.colors) {
        needSingle("a packed colour");
        if (field.size != 4) {
          failField(file, field.name, "a packed colour of 4 bytes (type F or U)",
                    std::to_string(field.size) + " bytes");
        }
        c.target = name == "rgba" ? Target::Rgba : Target::Rgb;
        layout.colors = true;
        layout.alpha = name == "rgba";
      } else if (normals && single && name.starts_with("normal_") && name.size() == 8 &&
                 name[7] >= 'x' && name[7] <= 'z') {
        c.target = name[7] == 'x' ? Target::Nx : name[7] == 'y' ? Target::Ny : Target::Nz;
        layout.normals = true;
        layout.source.normal = scalarTypeOf(field.type, field.size);
      } else if (channel_colors && (name == "red" || name == "green" || name == "blue")) {
        c.target = name == "red" ? Target::Red : name == "green" ? Target::Green : Target::Blue;
        layout.colors = layout.channel_colors = true;
        layout.wide_colors |= field.size > 1 || field.type == 'F';
      } else if (name == "intensity" && single && !layout.intensity) {
        c.target = Target::Intensity;
        layout.intensity = true;
        layout.source.intensity = scalarTypeOf(field.type, field.size);
      } else if (name == "classification" && single && !layout.classification) {
        c.target = Target::Classification;
        layout.classification = true;
        layout.source.classification = scalarTypeOf(field.type, field.size);
      } else if (name == "_") {
        c.target = Target::Skip;
      } else {
        c.target = Target::Scalar;
        c.scalar = layout.scalars.size();
        // A LAS field under its model name, unless a field of the file already holds that name.
        const char* las_name = single ? lasFieldColumn(lasFieldNamed(name)) : nullptr;
        if (las_name != nullptr &&
            std::none_of(layout.scalars.begin(), layout.scalars.end(),
                         [&](const auto& s) { return s.first == las_name; }) &&
            header.find(las_name) < 0) {
          c.name = las_name;
        }
        layout.scalars.emplace_back(c.name, scalarTypeOf(field.type, field.size));
      }
      // The source's order, under the model's names (writers give it back).
      switch (c.target) {
        case Target::X:
          layout.source.order.push_back(column_names::kX);
          break;
        case Target::Y:
          layout.source.order.push_back(column_names::kY);
          break;
        case Target::Z:
          layout.source.order.push_back(column_names::kZ);
          break;
        case Target::Rgb:
        case Target::Rgba:
          layout.source.order.insert(
              layout.source.order.end(),
              {column_names::kRed, column_names::kGreen, column_names::kBlue});
          if (c.target == Target::Rgba) layout.source.order.push_back(column_names::kAlpha);
          break;
        case Target::Red:
          layout.source.order.push_back(column_names::kRed);
          break;
        case Target::Green:
          layout.source.order.push_back(column_names::kGreen);
          break;
        case Target::Blue:
          layout.source.order.push_back(column_names::kBlue);
          break;
        case Target::Classification:
          layout.source.order.push_back(column_names::kClassification);
          break;
        case Target::Nx:
          layout.source.order.push_back(column_names::kNx);
          break;
        case Target::Ny:
          layout.source.order.push_back(column_names::kNy);
          break;
        case Target::Nz:
          layout.source.order.push_back(column_names::kNz);
          break;
        case Target::Intensity:
          layout.source.order.push_back(column_names::kIntensity);
          break;
        case Target::Scalar:
          layout.source.order.push_back(c.name);
          break;
        case Target::Skip:
          break;
      }
      layout.components.push_back(std::move(c));
    }
  }
  for (int axis = 0; axis < 3; ++axis) {
    if (!has[axis]) {
      failField(file, std::string(1, char('x' + axis)), "fields x, y and z (the point's position)",
                "no field '" + std::string(1, char('x' + axis)) + "' in FIELDS");
    }
  }
  layout.source.has_alpha = layout.alpha;
  layout.source.color = ScalarType::UInt8;
  return layout;
}

DataView binaryView(const PcdHeader& header, const Layout& layout, const std::byte* data,
                    std::uint64_t records) {
  DataView view;
  view.records = records;
  for (const Component& c : layout.components) {
    const PcdField& field = header.fields[c.field];
    view.components.push_back({data + field.offset + std::size_t(c.index) * field.size,
                               header.record_size, c.type, c.size});
  }
  return view;
}

DataView compressedView(const PcdHeader& header, const Layout& layout, const std::byte* data,
                        std::uint64_t records) {
  // Field f's block holds every point's values of f: it starts after the blocks of the fields
  // before it, records * (their size * count) bytes.
  DataView view;
  view.records = records;
  for (const Component& c : layout.components) {
    const PcdField& field = header.fields[c.field];
    view.components.push_back({data + records * field.offset + std::size_t(c.index) * field.size,
                               std::size_t(field.size) * field.count, c.type, c.size});
  }
  return view;
}

DataView AsciiTable::view(const Layout& layout) const {
  DataView view;
  view.records = records;
  const std::size_t stride = layout.components.size() * sizeof(double);
  const auto* base = reinterpret_cast<const std::byte*>(values.data());
  for (std::size_t i = 0; i < layout.components.size(); ++i) {
    view.components.push_back({base + i * sizeof(double), stride, 'F', 8});
  }
  return view;
}

AsciiTable parseAscii(std::string_view text, std::size_t begin, std::uint64_t line,
                      std::uint64_t max_records, const Layout& layout, const std::string& file) {
  AsciiTable table;
  const std::size_t width = layout.components.size();
  // Reserve no more than the bytes can hold (two characters a value at least).
  const std::uint64_t possible = (text.size() - std::min(begin, text.size())) / (2 * width) + 1;
  table.values.reserve(std::size_t(std::min(max_records, possible)) * width);
  const char* p = text.data() + begin;
  const char* const end = text.data() + text.size();
  auto blank = [](char c) { return c == ' ' || c == '\t' || c == '\r'; };
  while (table.records < max_records && p < end) {
    const char* newline = static_cast<const char*>(std::memchr(p, '\n', std::size_t(end - p)));
    const char* line_end = newline ? newline : end;
    const char* q = p;
    while (q < line_end && blank(*q)) ++q;
    if (q == line_end) {  // blank line
      p = newline ? newline + 1 : end;
      ++line;
      continue;
    }
    for (std::size_t i = 0; i < width; ++i) {
      const Component& c = layout.components[i];
      while (q < line_end && blank(*q)) ++q;
      auto fail = [&](const std::string& expected, const std::string& found) {
        throw InputError({.file = file,
                          .line = line,
                          .element = "ascii data",
                          .property = c.name,
                          .expected = expected,
                          .found = found});
      };
      if (q == line_end) {
        fail(std::to_string(width) + " values on the line (one per field value)",
             std::to_string(i));
      }
      const char* token_end = q;
      while (token_end < line_end && !blank(*token_end)) ++token_end;
      double value = 0;
      if (c.type == 'F' && c.size == 4 && c.target != Target::Rgb && c.target != Target::Rgba) {
        float narrow = 0;  // the float nearest to the text, as PCL parses it
        auto result = fast_float::from_chars(q, token_end, narrow);
        if (result.ec != std::errc() || result.ptr != token_end) {
          fail("a number", quoted({q, std::size_t(token_end - q)}));
        }
        value = narrow;
      } else {
        auto result = fast_float::from_chars(q, token_end, value);
        if (result.ec != std::errc() || result.ptr != token_end) {
          fail("a number", quoted({q, std::size_t(token_end - q)}));
        }
        if (c.type != 'F') {
          double lo = 0, hi = 0;
          dispatch(c.type, c.size, [&](auto tag) {
            using T = decltype(tag);
            lo = double(std::numeric_limits<T>::min());
            hi = double(std::numeric_limits<T>::max());
          });
          if (!(value >= lo && value <= hi) || value != std::floor(value)) {
            fail("an integer of type " + std::string(1, c.type) + std::to_string(c.size),
                 quoted({q, std::size_t(token_end - q)}));
          }
        } else if (c.target == Target::Rgb || c.target == Target::Rgba) {
          // A packed colour of type F is the bits of a float: parsed as a float. (PCL writes it
          // back as an unsigned integer, which it reads as such.)
          value = double(std::bit_cast<std::uint32_t>(float(value)));
        }
      }
      table.values.push_back(value);
      q = token_end;
    }
    while (q < line_end && blank(*q)) ++q;
    if (q != line_end) {
      throw InputError({.file = file,
                        .line = line,
                        .element = "ascii data",
                        .expected = std::to_string(width) + " values (one per field value)",
                        .found = "more: '" + quoteInput({q, std::size_t(line_end - q)}) + "'"});
    }
    ++table.records;
    p = newline ? newline + 1 : end;
    ++line;
  }
  table.end = std::size_t(p - text.data());
  table.next_line = line;
  return table;
}

void decompress(std::span<const std::byte> bytes, const PcdHeader& header, const std::string& file,
                std::vector<std::byte>& out) {
  const std::size_t at = header.data_offset;
  auto fail = [&](std::size_t offset, const std::string& property, const std::string& expected,
                  const std::string& found) {
    throw InputError({.file = file,
                      .byte_offset = offset,
                      .element = "binary_compressed data",
                      .property = property,
                      .expected = expected,
                      .found = found});
  };
  if (bytes.size() < at + 8) {
    fail(at, "sizes", "two 4-byte sizes (compressed, uncompressed) after DATA",
         std::to_string(bytes.size() - std::min(bytes.size(), at)) + " bytes");
  }
  const auto compressed = loadLE<std::uint32_t>(bytes.data() + at);
  const auto uncompressed = loadLE<std::uint32_t>(bytes.data() + at + 4);
  const std::uint64_t expected = header.points * header.record_size;
  if (uncompressed != expected) {
    fail(at + 4, "uncompressed size",
         std::to_string(expected) + " bytes (POINTS " + std::to_string(header.points) + " * " +
             std::to_string(header.record_size) + " bytes a point)",
         std::to_string(uncompressed));
  }
  if (compressed > bytes.size() - at - 8) {
    fail(at, "compressed size",
         "at most the " + std::to_string(bytes.size() - at - 8) + " bytes left in the file",
         std::to_string(compressed) + " (the file is truncated)");
  }
  // LZF expands at most about 100 times (a 3-byte back reference copies 264 bytes): a larger
  // claim is a lying header, refused before allocating it.
  if (expected > std::uint64_t(compressed) * 100 + 64) {
    fail(at + 4, "uncompressed size", "at most 100 times the compressed size",
         std::to_string(uncompressed) + " from " + std::to_string(compressed));
  }
  out.resize(expected);
  if (expected == 0) return;
  const unsigned got = lzf_decompress(bytes.data() + at + 8, compressed, out.data(), uncompressed);
  if (got != uncompressed) {
    fail(at + 8, "LZF data", "LZF data decompressing to " + std::to_string(uncompressed) + " bytes",
         got == 0 ? "corrupt data (liblzf refused it)" : std::to_string(got) + " bytes");
  }
}

PositionScan scanPositions(const DataView& view, const Layout& layout, std::uint64_t begin,
                           std::uint64_t end) {
  PositionScan scan;
  const ComponentView& x = view.components[layout.x];
  const ComponentView& y = view.components[layout.y];
  const ComponentView& z = view.components[layout.z];
  double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  std::uint64_t valid = 0;
  auto run = [&](auto xt, auto yt, auto zt) {
    using X = decltype(xt);
    using Y = decltype(yt);
    using Z = decltype(zt);
    for (std::uint64_t i = begin; i < end; ++i) {
      const double v[3] = {double(loadLE<X>(x.base + i * x.stride)),
                           double(loadLE<Y>(y.base + i * y.stride)),
                           double(loadLE<Z>(z.base + i * z.stride))};
      if (!(std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]))) continue;
      ++valid;
      for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], v[a]), hi[a] = std::max(hi[a], v[a]);
    }
  };
  if (x.type == 'F' && y.type == 'F' && z.type == 'F' && x.size == y.size && y.size == z.size) {
    if (x.size == 4) {
      run(float{}, float{}, float{});
    } else {
      run(double{}, double{}, double{});
    }
  } else {
    dispatch(x.type, x.size, [&](auto xt) {
      dispatch(y.type, y.size,
               [&](auto yt) { dispatch(z.type, z.size, [&](auto zt) { run(xt, yt, zt); }); });
    });
  }
  scan.valid = valid;
  if (valid > 0) {
    scan.bounds.extend(lo[0], lo[1], lo[2]);
    scan.bounds.extend(hi[0], hi[1], hi[2]);
  }
  if (layout.wide_colors) {
    // Every record's channels, invalid points' too: the rule is the file's, and a channel of an
    // invalid point is still a value the writer of the file gave (PDAL writes no invalid ones).
    for (std::size_t k = 0; k < layout.components.size() && !scan.color_above_255; ++k) {
      const Target t = layout.components[k].target;
      if (t != Target::Red && t != Target::Green && t != Target::Blue) continue;
      const ComponentView& c = view.components[k];
      dispatch(c.type, c.size, [&](auto tag) {
        using T = decltype(tag);
        for (std::uint64_t i = begin; i < end; ++i) {
          if (loadLE<T>(c.base + i * c.stride) > T(255)) {
            scan.color_above_255 = true;
            break;
          }
        }
      });
    }
  }
  return scan;
}

namespace {

// The records to decode: [begin, end) when all are valid, else the valid ones listed.
struct Records {
  std::uint64_t begin = 0;
  const std::uint32_t* list = nullptr;  // offsets from begin; null: every record
  std::uint64_t count = 0;
  std::uint64_t operator[](std::uint64_t j) const { return begin + (list ? list[j] : j); }
};

// A colour channel or a classification from a value of any type: rounded and clamped to
// [0, max], NaN giving 0 (a float field may hold anything; converting NaN to an integer is
// undefined behaviour, and UBSan stopped the fuzz target on a NaN classification).
double pcdRoundClamped(double value, double max) {
  if (std::isnan(value)) return 0.0;
  return std::clamp(std::nearbyint(value), 0.0, max);
}

template <class Out, class Convert>
void decodeComponent(const ComponentView& c, const Records& records, Out* out,
                     std::size_t out_stride, Convert convert) {
  dispatch(c.type, c.size, [&](auto tag) {
    using T = decltype(tag);
    for (std::uint64_t j = 0; j < records.count; ++j) {
      out[j * out_stride] = convert(loadLE<T>(c.base + records[j] * c.stride));
    }
  });
}

}  // namespace

void decodeRecords(const DataView& view, const Layout& layout, std::uint64_t begin,
                   std::uint64_t end, std::uint64_t valid, PointCloud& cloud,
                   std::uint64_t first_index) {
  std::vector<std::uint32_t> list;
  Records records{.begin = begin, .count = valid};
  if (valid != end - begin) {
    list.reserve(valid);
    const ComponentView& x = view.components[layout.x];
    const ComponentView& y = view.components[layout.y];
    const ComponentView& z = view.components[layout.z];
    for (std::uint64_t i = begin; i < end; ++i) {
      double v[3];
      dispatch(x.type, x.size,
               [&](auto t) { v[0] = double(loadLE<decltype(t)>(x.base + i * x.stride)); });
      dispatch(y.type, y.size,
               [&](auto t) { v[1] = double(loadLE<decltype(t)>(y.base + i * y.stride)); });
      dispatch(z.type, z.size,
               [&](auto t) { v[2] = double(loadLE<decltype(t)>(z.base + i * z.stride)); });
      if (std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2])) {
        list.push_back(std::uint32_t(i - begin));
      }
    }
    records.list = list.data();
    records.count = list.size();
  }
  if (records.count == 0) return;
  const Quantization& q = cloud.quantization;
  for (const Component& c : layout.components) {
    const ComponentView& v = view.components[std::size_t(&c - layout.components.data())];
    switch (c.target) {
      case Target::X:
      case Target::Y:
      case Target::Z: {
        const int axis = c.target == Target::X ? 0 : c.target == Target::Y ? 1 : 2;
        const double offset = q.offset[axis], inverse = 1.0 / q.scale[axis];
        std::int32_t* out = &cloud.positions[first_index].x + axis;
        decodeComponent(v, records, out, 3, [&](auto value) {
          return ply::quantizeClamped(double(value), offset, inverse);
        });
        break;
      }
      case Target::Rgb:
      case Target::Rgba: {
        const bool alpha = c.target == Target::Rgba;
        Rgba8* out = &cloud.colors[first_index];
        decodeComponent(v, records, out, 1, [&](auto value) {
          std::uint32_t bits = 0;
          using T = decltype(value);
          if constexpr (std::is_same_v<T, float>) {
            bits = std::bit_cast<std::uint32_t>(value);
          } else if constexpr (std::is_same_v<T, double>) {
            bits = std::uint32_t(value);  // ascii: the bits, already as an integer
          } else {
            bits = std::uint32_t(value);
          }
          return Rgba8{std::uint8_t(bits >> 16), std::uint8_t(bits >> 8), std::uint8_t(bits),
                       alpha ? std::uint8_t(bits >> 24) : std::uint8_t(255)};
        });
        break;
      }
      case Target::Red:
      case Target::Green:
      case Target::Blue: {
        const int channel = c.target == Target::Red ? 0 : c.target == Target::Green ? 1 : 2;
        if (layout.wide_colors) {
          std::uint16_t* out = &cloud.stored_colors[first_index].r + channel;
          decodeComponent(v, records, out, 3, [](auto value) {
            return std::uint16_t(pcdRoundClamped(double(value), 65535.0));
          });
        } else {
          std::uint8_t* out = &cloud.colors[first_index].r + channel;
          decodeComponent(v, records, out, 4, [](auto value) {
            return std::uint8_t(pcdRoundClamped(double(value), 255.0));
          });
        }
        break;
      }
      case Target::Classification:
        decodeComponent(v, records, &cloud.classification[first_index], 1, [](auto value) {
          return std::uint8_t(pcdRoundClamped(double(value), 255.0));
        });
        break;
      case Target::Nx:
      case Target::Ny:
      case Target::Nz: {
        const int axis = c.target == Target::Nx ? 0 : c.target == Target::Ny ? 1 : 2;
        float* out = &cloud.normals[first_index].x + axis;
        decodeComponent(v, records, out, 3, [](auto value) { return float(value); });
        break;
      }
      case Target::Intensity:
        decodeComponent(v, records, &cloud.intensity[first_index], 1,
                        [](auto value) { return float(value); });
        break;
      case Target::Scalar: {
        ScalarColumn& column = cloud.scalars[c.scalar];
        auto store = [&](auto out_tag) {
          using O = decltype(out_tag);
          O* out = column.as<O>() + first_index;
          decodeComponent(v, records, out, 1, [](auto value) { return O(value); });
        };
        switch (column.type) {
          case ScalarType::Int8:
            store(std::int8_t{});
            break;
          case ScalarType::UInt8:
            store(std::uint8_t{});
            break;
          case ScalarType::Int16:
            store(std::int16_t{});
            break;
          case ScalarType::UInt16:
            store(std::uint16_t{});
            break;
          case ScalarType::Int32:
            store(std::int32_t{});
            break;
          case ScalarType::UInt32:
            store(std::uint32_t{});
            break;
          case ScalarType::Float32:
            store(float{});
            break;
          case ScalarType::Float64:
            store(double{});
            break;
        }
        break;
      }
      case Target::Skip:
        break;
    }
  }
  if (layout.channel_colors) {
    // The display colours of channel fields: opaque, and from the stored 16 bits by the rule.
    Rgba8* colors = &cloud.colors[first_index];
    if (layout.wide_colors) {
      const Rgb16* stored = &cloud.stored_colors[first_index];
      auto to8 = [&](std::uint16_t value) { return shownColor(value, layout.colors_8bit); };
      for (std::uint64_t j = 0; j < records.count; ++j) {
        colors[j] = {to8(stored[j].r), to8(stored[j].g), to8(stored[j].b), 255};
      }
    } else {
      for (std::uint64_t j = 0; j < records.count; ++j) colors[j].a = 255;
    }
  }
}

PointCloud allocateCloud(const Layout& layout, std::uint64_t count, const Quantization& q) {
  PointCloud cloud;
  cloud.count = count;
  cloud.quantization = q;
  cloud.positions = Column<Int3>(count);
  if (layout.colors) cloud.colors = Column<Rgba8>(count);
  if (layout.wide_colors) cloud.stored_colors = Column<Rgb16>(count);
  if (layout.classification) cloud.classification = Column<std::uint8_t>(count);
  if (layout.normals) cloud.normals = Column<Float3>(count);
  if (layout.intensity) cloud.intensity = Column<float>(count);
  for (const auto& [name, type] : layout.scalars) {
    cloud.scalars.push_back(
        {.name = name, .type = type, .data = ByteBuffer(count * scalarSize(type))});
  }
  cloud.source = layout.source;
  // As las_reader.h tells 16-bit colour from 8-bit values in 16-bit fields.
  if (layout.wide_colors && !layout.colors_8bit) cloud.source.color = ScalarType::UInt16;
  return cloud;
}

}  // namespace parallax::pcd
