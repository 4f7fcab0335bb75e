#include "io/las_writer.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cassert>
#include <charconv>
#include <cmath>
#include <cstring>
#include <optional>

#include "core/byte_order.h"
#include "core/color_depth.h"
#include "core/column_names.h"
#include "io/las_field_names.h"
#include "io/las_reader.h"
#include "io/laz/laz_layout.h"
#include "io/laz_writer.h"
#include "io/point_file.h"

namespace parallax {
namespace {

struct Source {
  const std::byte* data = nullptr;
  ScalarType type = ScalarType::UInt8;
  std::size_t stride = 0;  // bytes from one value to the next; 0: the type's size (a column)
};

// Component `axis` of the cloud's normals (interleaved Float3) as a Source.
Source normalComponentSource(const PointCloud& cloud, int axis) {
  return {reinterpret_cast<const std::byte*>(cloud.normals.data()) + 4 * axis, ScalarType::Float32,
          sizeof(Float3)};
}

Source sourceOf(const ScalarColumn& column) {
  return {column.data.data(), column.type};
}

template <class F>
void withType(ScalarType type, F f) {
  switch (type) {
    case ScalarType::Int8:
      f(std::int8_t{});
      break;
    case ScalarType::UInt8:
      f(std::uint8_t{});
      break;
    case ScalarType::Int16:
      f(std::int16_t{});
      break;
    case ScalarType::UInt16:
      f(std::uint16_t{});
      break;
    case ScalarType::Int32:
      f(std::int32_t{});
      break;
    case ScalarType::UInt32:
      f(std::uint32_t{});
      break;
    case ScalarType::Float32:
      f(float{});
      break;
    case ScalarType::Float64:
      f(double{});
      break;
  }
}

void gather(const Source& source, std::size_t first, std::size_t n, double* out) {
  withType(source.type, [&](auto zero) {
    using T = decltype(zero);
    if (source.stride != 0) {
      const std::byte* at = source.data + first * source.stride;
      for (std::size_t i = 0; i < n; ++i) out[i] = double(loadLE<T>(at + i * source.stride));
      return;
    }
    const T* values = reinterpret_cast<const T*>(source.data) + first;
    for (std::size_t i = 0; i < n; ++i) out[i] = double(values[i]);
  });
}

double maximum(const Source& source, std::size_t count) {
  double best = 0.0;
  withType(source.type, [&](auto zero) {
    using T = decltype(zero);
    const T* values = reinterpret_cast<const T*>(source.data);
    T m = T(0);
    for (std::size_t i = 0; i < count; ++i) m = std::max(m, values[i]);
    best = double(m);
  });
  return best;
}

// A bit field packed into one byte of the record: value clamped to 0..max, shifted.
struct BitTarget {
  Source source;
  std::size_t offset;
  int shift;
  unsigned max;
};
// A whole value converted (times `factor`, rounded for integers, clamped) into `type`, or into
// a uint64 (wave packet offsets) when `type` is absent.
struct ValueTarget {
  Source source;
  std::size_t offset;
  std::optional<ScalarType> type;
  double factor;
};
// One value of the source's extra bytes, stored back in its own data type (LAS 1.4 R15 Table
// 24: 1-10 are uchar, char, ushort, short, ulong, long, ulonglong, longlong, float, double; 0,
// undocumented bytes, is one uchar here): raw = (value - add) / scale, rounded for integers.
// A null source (the cloud lost that column) leaves the bytes zero.
struct SourceExtraTarget {
  Source source;
  std::size_t offset;
  int data_type;
  double scale, add;
};
// An extra-bytes column copied in its own type.
struct RawTarget {
  Source source;
  std::size_t offset;
  std::size_t size;
};

struct Layout {
  LasWritePlan plan;
  std::vector<BitTarget> bits;
  std::vector<ValueTarget> values;
  std::vector<RawTarget> raws;
  std::vector<SourceExtraTarget> source_extras;
  std::vector<std::byte> source_extra_descriptors;  // the source's LASF_Spec 4 payload, verbatim
  std::vector<std::pair<std::string, ScalarType>> extra_types;
  std::optional<std::size_t> color_offset;
  Source return_number;  // data null when absent
};

std::uint8_t extraDataType(ScalarType type) {
  switch (type) {
    case ScalarType::UInt8:
      return 1;
    case ScalarType::Int8:
      return 2;
    case ScalarType::UInt16:
      return 3;
    case ScalarType::Int16:
      return 4;
    case ScalarType::UInt32:
      return 5;
    case ScalarType::Int32:
      return 6;
    case ScalarType::Float32:
      return 9;
    case ScalarType::Float64:
      return 10;
  }
  return 0;
}

// Whether a source's VLR or EVLR is carried over: not the records describing the source's own
// compression or layout (LASzip's, COPC's), which the writer makes anew or which would lie.
bool carriedLasRecord(const LasVlr& vlr) {
  return vlr.user_id != laz::kLaszipUserId && vlr.user_id != "copc" &&
         vlr.user_id != "lascompatible";
}

// The layout of `cloud`'s columns in the records of a file of `point_count` points. Without
// `decided`, the version and point format are chosen from the columns and their maxima (the
// cloud's); with it, they are decided's, so that the batches of one streamed file all bind their
// columns to the one layout chosen for the file.
Layout makeLayout(const PointCloud& cloud, const LasWriteOptions& options,
                  std::uint64_t point_count, const LasWritePlan* decided = nullptr) {
  Layout layout;
  LasWritePlan& plan = layout.plan;
  const std::size_t count = cloud.count;
  std::vector<std::pair<LasField, const ScalarColumn*>> mapped;
  std::vector<const ScalarColumn*> extras;
  auto find = [&](LasField field) -> const ScalarColumn* {
    for (const auto& [f, column] : mapped) {
      if (f == field) return column;
    }
    return nullptr;
  };
  for (const ScalarColumn& column : cloud.scalars) {
    LasField field = lasFieldNamed(column.name);
    if (field == LasField::None || find(field) != nullptr) {
      extras.push_back(&column);
    } else {
      mapped.emplace_back(field, &column);
    }
  }
  auto maxOf = [&](LasField field) {
    const ScalarColumn* column = find(field);
    return column ? maximum(sourceOf(*column), count) : 0.0;
  };
  double max_class = cloud.hasClassification()
                         ? maximum({reinterpret_cast<const std::byte*>(cloud.classification.data()),
                                    ScalarType::UInt8},
                                   count)
                         : 0.0;

  const LasHeader* src = options.source.get();
  // The first field the cloud holds that only formats 6-10 have room for; null when none.
  const char* extended_field = find(LasField::Channel)                ? "scanner_channel"
                               : max_class > 31                       ? "classification above 31"
                               : maxOf(LasField::ReturnNumber) > 7    ? "return_number above 7"
                               : maxOf(LasField::NumberOfReturns) > 7 ? "number_of_returns above 7"
                               : maxOf(LasField::ClassFlags) >= 8 || maxOf(LasField::Overlap) > 0
                                   ? "the overlap flag"
                               : find(LasField::ScanAngle) && !find(LasField::ScanAngleRank)
                                   ? "scan_angle (0.006 degree steps)"
                                   : nullptr;
  const bool has_wave = find(LasField::WaveIndex) || find(LasField::WaveOffset) ||
                        find(LasField::WaveSize) || find(LasField::WaveLocation);
  const bool format_forced = options.point_format >= 0;
  assert(options.point_format <= kLasMaxPointFormat && "LAS point format must be 0-10");
  assert(
      (options.minor_version == 0 || (options.minor_version >= 2 && options.minor_version <= 4)) &&
      "a forced LAS minor version must be 2, 3 or 4");
  int format = 0;
  int minor = options.minor_version;
  if (decided) {
    format = decided->point_format;
    minor = decided->minor_version;
  } else if (format_forced) {
    format = options.point_format;
  } else if (src) {
    format = src->point_format;
    // The source's format grows (never shrinks) to hold what the cloud has.
    const bool ext = lasFormatIsExtended(format) || extended_field || find(LasField::Nir);
    const bool gps = lasFormatHasGpsTime(format) || find(LasField::GpsTime);
    const bool color = lasFormatHasColor(format) || cloud.hasColors();
    const bool nir = lasFormatHasNir(format) || find(LasField::Nir);
    const bool wave = lasFormatHasWavePacket(format) || has_wave;
    const int grown = lasFormatHolding(ext, gps, color, nir, wave);
    if (grown != format) {
      const std::string why = extended_field && !lasFormatIsExtended(format) ? extended_field
                              : nir && !lasFormatHasNir(format)              ? column_names::kNir
                              : color && !lasFormatHasColor(format)          ? "red, green, blue"
                              : gps && !lasFormatHasGpsTime(format) ? column_names::kGpsTime
                                                                    : "wave packets";
      plan.changes.push_back("point format " + std::to_string(format) + " -> " +
                             std::to_string(grown) + ": the points' " + why +
                             " has no field in format " + std::to_string(format));
      format = grown;
    }
  } else {
    if (minor == 0) {
      bool needs14 = extended_field || find(LasField::Nir) || point_count > UINT32_MAX;
      minor = needs14 ? 4 : 2;
    }
    if (minor == 4) {
      format = find(LasField::Nir) ? 8 : cloud.hasColors() ? 7 : 6;
    } else {
      format = (find(LasField::GpsTime) ? 1 : 0) + (cloud.hasColors() ? 2 : 0);
    }
  }
  if (minor == 0) {
    minor = std::max(src ? int(src->version_minor) : 2, lasMinorVersionFor(format));
    if (src && minor > src->version_minor) {
      plan.changes.push_back("LAS 1." + std::to_string(src->version_minor) + " -> 1." +
                             std::to_string(minor) + ": point format " + std::to_string(format) +
                             " needs it");
    }
  } else if (lasMinorVersionFor(format) > minor) {
    if (format_forced) {
      throw std::invalid_argument("point format " + std::to_string(format) + " needs LAS 1." +
                                  std::to_string(lasMinorVersionFor(format)) +
                                  " or later, and LAS 1." + std::to_string(minor) +
                                  " was asked for");
    }
    // The version was asked for: the format shrinks to one it holds.
    const int shrunk =
        lasFormatHolding(false, lasFormatHasGpsTime(format), lasFormatHasColor(format), false,
                         lasFormatHasWavePacket(format) && minor >= 3);
    plan.losses.push_back("point format " + std::to_string(format) + " -> " +
                          std::to_string(shrunk) + " (LAS 1." + std::to_string(minor) +
                          " has no format " + std::to_string(format) + ")");
    format = shrunk;
  }
  for (const std::string& change : plan.changes) plan.losses.push_back(change);
  plan.minor_version = minor;
  plan.point_format = format;
  const bool ext = lasFormatIsExtended(format);
  std::size_t record = lasPointFormatSize(format);

  auto bit = [&](LasField field, std::size_t offset, int shift, unsigned max) {
    if (const ScalarColumn* column = find(field)) {
      layout.bits.push_back({sourceOf(*column), offset, shift, max});
      if (maxOf(field) > max) {
        plan.losses.push_back(column->name + " clamped to " + std::to_string(max) +
                              " (point format " + std::to_string(format) + " field width)");
      }
    }
  };
  auto value = [&](LasField field, std::size_t offset, std::optional<ScalarType> type,
                   double factor = 1.0) {
    if (const ScalarColumn* column = find(field)) {
      layout.values.push_back({sourceOf(*column), offset, type, factor});
    }
  };
  // A field the format has no place for is kept as extra bytes.
  auto extra = [&](LasField field) {
    if (const ScalarColumn* column = find(field)) extras.push_back(column);
  };
  if (cloud.hasClassification()) {
    Source cls{reinterpret_cast<const std::byte*>(cloud.classification.data()), ScalarType::UInt8};
    if (ext) {
      layout.values.push_back({cls, 16, ScalarType::UInt8, 1.0});
    } else {
      layout.bits.push_back({cls, 15, 0, 31});
      if (max_class > 31) {
        plan.losses.push_back("classification above 31 clamped (point format " +
                              std::to_string(format) + ")");
      }
    }
  }
  if (ext) {
    bit(LasField::ReturnNumber, 14, 0, 15);
    bit(LasField::NumberOfReturns, 14, 4, 15);
    bit(LasField::ClassFlags, 15, 0, 15);
    bit(LasField::Synthetic, 15, 0, 1);
    bit(LasField::KeyPoint, 15, 1, 1);
    bit(LasField::Withheld, 15, 2, 1);
    bit(LasField::Overlap, 15, 3, 1);
    bit(LasField::Channel, 15, 4, 3);
    bit(LasField::ScanDirection, 15, 6, 1);
    bit(LasField::Edge, 15, 7, 1);
    value(LasField::UserData, 17, ScalarType::UInt8);
    if (find(LasField::ScanAngle)) {
      value(LasField::ScanAngle, 18, ScalarType::Int16);
    } else {
      value(LasField::ScanAngleRank, 18, ScalarType::Int16, 1.0 / 0.006);  // degrees to 0.006°
    }
    value(LasField::PointSourceId, 20, ScalarType::UInt16);
    value(LasField::GpsTime, 22, ScalarType::Float64);
    if (find(LasField::ScanAngleRank) && find(LasField::ScanAngle)) extra(LasField::ScanAngleRank);
  } else {
    bit(LasField::ReturnNumber, 14, 0, 7);
    bit(LasField::NumberOfReturns, 14, 3, 7);
    bit(LasField::ScanDirection, 14, 6, 1);
    bit(LasField::Edge, 14, 7, 1);
    bit(LasField::ClassFlags, 15, 5, 7);
    bit(LasField::Synthetic, 15, 5, 1);
    bit(LasField::KeyPoint, 15, 6, 1);
    bit(LasField::Withheld, 15, 7, 1);
    if (find(LasField::ScanAngleRank)) {
      value(LasField::ScanAngleRank, 16, ScalarType::Int8);
    } else {
      value(LasField::ScanAngle, 16, ScalarType::Int8, 0.006);
    }
    value(LasField::UserData, 17, ScalarType::UInt8);
    value(LasField::PointSourceId, 18, ScalarType::UInt16);
    if (lasFormatHasGpsTime(format)) value(LasField::GpsTime, 20, ScalarType::Float64);
    // Fields formats 0-5 have no place for become extra bytes.
    extra(LasField::Channel);
    extra(LasField::Overlap);
    if (find(LasField::ScanAngleRank) && find(LasField::ScanAngle)) extra(LasField::ScanAngle);
  }
  if (!lasFormatHasGpsTime(format)) extra(LasField::GpsTime);
  if (lasFormatHasColor(format)) {
    layout.color_offset = ext ? 30 : format == 2 ? 20 : 28;
  } else if (cloud.hasColors()) {
    plan.losses.push_back("red, green, blue (point format " + std::to_string(format) +
                          " has no colour)");
  }
  if (lasFormatHasNir(format)) {
    value(LasField::Nir, 36, ScalarType::UInt16);
  } else {
    extra(LasField::Nir);
  }
  // LAS 1.4 R15 Table 13: index, offset, size, location, x(t), y(t), z(t), the last 29 bytes.
  const std::size_t wave = lasPointFormatSize(format) - 29;
  for (auto [field, offset, type] :
       {std::tuple{LasField::WaveIndex, 0, std::optional(ScalarType::UInt8)},
        std::tuple{LasField::WaveOffset, 1, std::optional<ScalarType>()},
        std::tuple{LasField::WaveSize, 9, std::optional(ScalarType::UInt32)},
        std::tuple{LasField::WaveLocation, 13, std::optional(ScalarType::Float32)},
        std::tuple{LasField::WaveDx, 17, std::optional(ScalarType::Float32)},
        std::tuple{LasField::WaveDy, 21, std::optional(ScalarType::Float32)},
        std::tuple{LasField::WaveDz, 25, std::optional(ScalarType::Float32)}}) {
    if (lasFormatHasWavePacket(format)) {
      value(field, wave + std::size_t(offset), type);
    } else {
      extra(field);
    }
  }
  if (const ScalarColumn* column = find(LasField::ReturnNumber))
    layout.return_number = sourceOf(*column);

  // The source's extra bytes, at their offsets after the fixed fields, from the columns the
  // reader made of them (matched by name).
  bool normals_placed = false;  // in the source's own normals' extra bytes
  const auto undescribed = [](const ScalarColumn* column) {
    return lasUndescribedByteOffset(column->name).has_value();
  };
  if (src &&
      (!src->extra_bytes.empty() || std::any_of(extras.begin(), extras.end(), undescribed))) {
    const std::size_t src_fixed = lasPointFormatSize(src->point_format);
    // The source's normals' extra bytes, which its reader gave as the cloud's normals: filled
    // from them again, at their places and in their types.
    const std::optional<std::array<std::size_t, 3>> src_normals =
        lasNormalExtraBytes(src->extra_bytes);
    for (std::size_t index = 0; index < src->extra_bytes.size(); ++index) {
      const LasExtraBytes& described = src->extra_bytes[index];
      auto it = std::find_if(extras.begin(), extras.end(), [&](const ScalarColumn* column) {
        return column->name == described.name;
      });
      const auto axis = src_normals ? std::find(src_normals->begin(), src_normals->end(), index)
                                    : std::array<std::size_t, 3>::const_iterator{};
      Source source;
      if (it != extras.end()) {
        source = sourceOf(**it);
        extras.erase(it);
      } else if (src_normals && axis != src_normals->end() && cloud.hasNormals()) {
        source = normalComponentSource(cloud, int(axis - src_normals->begin()));
        normals_placed = true;
      } else {
        plan.losses.push_back("extra bytes '" + described.name +
                              "' written as zeros (the points have no such column)");
      }
      const int base = described.data_type == 0    ? 1
                       : described.data_type <= 10 ? described.data_type
                                                   : (described.data_type - 1) % 10 + 1;
      layout.source_extras.push_back({source, record + described.record_offset - src_fixed, base,
                                      described.scaled ? described.scale : 1.0,
                                      described.scaled ? described.offset : 0.0});
    }
    // Undescribed bytes (the reader's one column a byte) go back where they were, raw and
    // without a description; those past the source's record would be a column of another file.
    for (auto it = extras.begin(); it != extras.end();) {
      const std::optional<std::size_t> at = lasUndescribedByteOffset((*it)->name);
      if (at && *at >= lasDescribedRecordEnd(*src) && *at < src->record_length &&
          (*it)->type == ScalarType::UInt8) {
        layout.raws.push_back({sourceOf(**it), record + *at - src_fixed, 1});
        it = extras.erase(it);
      } else {
        ++it;
      }
    }
    record += src->record_length - src_fixed;
    for (const LasVlr& vlr : src->vlrs) {
      if (vlr.user_id == "LASF_Spec" && vlr.record_id == 4) {
        layout.source_extra_descriptors = vlr.data;
        break;
      }
    }
  }

  // Extra bytes: normals, then the unmapped scalars, each in its own type.
  auto addExtra = [&](const std::string& name, Source source) {
    std::size_t size = scalarSize(source.type);
    layout.raws.push_back({source, record, size});
    layout.extra_types.emplace_back(name.substr(0, 32), source.type);
    plan.extra_bytes.push_back(name.substr(0, 32));
    if (name.size() > 32) plan.losses.push_back("name '" + name + "' cut to 32 characters");
    record += size;
  };
  if (cloud.hasNormals() && !normals_placed) {
    // Named as CloudCompare and PDAL name them, so that they read them back as normals.
    for (int axis = 0; axis < 3; ++axis) {
      layout.raws.push_back({normalComponentSource(cloud, axis), record, 0});  // size 0: normal
      const std::string name = kLasNormalExtraBytesNames[axis];
      layout.extra_types.emplace_back(name, ScalarType::Float32);
      plan.extra_bytes.push_back(name);
      record += 4;
    }
  }
  for (const ScalarColumn* column : extras) addExtra(column->name, sourceOf(*column));
  plan.record_length = record;
  if (record > 65535) {
    throw std::runtime_error("LAS writer: a point record of " + std::to_string(record) +
                             " bytes is over LAS's 65 535 (too many scalar columns)");
  }

  if (src && minor < 4) {
    const auto evlrs = std::count_if(src->vlrs.begin(), src->vlrs.end(), [](const LasVlr& vlr) {
      return vlr.extended && carriedLasRecord(vlr);
    });
    if (evlrs > 0) {
      plan.losses.push_back(std::to_string(evlrs) + " EVLRs (LAS 1." + std::to_string(minor) +
                            " has none)");
    }
  }
  if (cloud.source.has_alpha) plan.losses.push_back("alpha (LAS has no alpha)");
  if (cloud.hasIntensity()) {
    const double full_scale = cloud.source.intensity_full_scale;
    if (full_scale > 0.0) {
      char range[32];
      const auto end = std::to_chars(range, range + sizeof range, full_scale).ptr;
      plan.losses.push_back("intensity 0.." + std::string(range, end) +
                            " (the source format's scale) mapped onto 0..65535");
    } else {
      // Only worth a word when some value is not already a 16-bit integer.
      bool exact = std::all_of(cloud.intensity.begin(), cloud.intensity.end(), [](float v) {
        return v >= 0.0f && v <= 65535.0f && v == std::nearbyint(v);
      });
      if (!exact) plan.losses.push_back("intensity rounded and clamped to 16-bit integers");
    }
  }
  return layout;
}

template <class T>
T clampRound(double v) {
  if constexpr (std::is_floating_point_v<T>) {
    return T(v);
  } else {
    v = std::nearbyint(v);
    if (!(v >= double(std::numeric_limits<T>::min()))) return std::numeric_limits<T>::min();
    if (v > double(std::numeric_limits<T>::max())) return std::numeric_limits<T>::max();
    return T(v);
  }
}

void encodeBlock(const PointCloud& cloud, const Layout& layout, std::size_t first, std::size_t n,
                 std::byte* out, LasPointTotals& stats) {
  const std::size_t stride = layout.plan.record_length;
  std::memset(out, 0, n * stride);
  std::vector<double> values(n);
  const Int3* positions = cloud.positions.data() + first;
  for (std::size_t i = 0; i < n; ++i) {
    const Int3& p = positions[i];
    std::memcpy(out + i * stride, &p, 12);
    stats.addPosition(p);
  }
  if (cloud.hasIntensity()) {
    const float* intensity = cloud.intensity.data() + first;
    const double full_scale = cloud.source.intensity_full_scale;
    if (full_scale > 0.0) {
      const double k = 65535.0 / full_scale;
      for (std::size_t i = 0; i < n; ++i) {
        storeLE(out + i * stride + 12, clampRound<std::uint16_t>(double(intensity[i]) * k));
      }
    } else {
      for (std::size_t i = 0; i < n; ++i) {
        storeLE(out + i * stride + 12, clampRound<std::uint16_t>(intensity[i]));
      }
    }
  }
  for (const BitTarget& target : layout.bits) {
    gather(target.source, first, n, values.data());
    for (std::size_t i = 0; i < n; ++i) {
      double v = std::clamp(std::nearbyint(values[i]), 0.0, double(target.max));
      auto& byte = out[i * stride + target.offset];
      byte |= std::byte(unsigned(v) << target.shift);
    }
  }
  for (const ValueTarget& target : layout.values) {
    gather(target.source, first, n, values.data());
    if (!target.type) {
      for (std::size_t i = 0; i < n; ++i) {
        storeLE(out + i * stride + target.offset, clampRound<std::uint64_t>(values[i]));
      }
      continue;
    }
    withType(*target.type, [&](auto zero) {
      using T = decltype(zero);
      for (std::size_t i = 0; i < n; ++i) {
        storeLE(out + i * stride + target.offset, clampRound<T>(values[i] * target.factor));
      }
    });
  }
  for (const SourceExtraTarget& target : layout.source_extras) {
    if (!target.source.data) continue;
    gather(target.source, first, n, values.data());
    withExtraDataType(target.data_type, [&](auto zero) {
      using T = decltype(zero);
      for (std::size_t i = 0; i < n; ++i) {
        const double raw = target.scale == 1.0 && target.add == 0.0
                               ? values[i]
                               : (values[i] - target.add) / target.scale;
        storeLE(out + i * stride + target.offset, clampRound<T>(raw));
      }
    });
  }
  if (layout.color_offset && cloud.hasStoredColors()) {
    // The values as the source stored them: never scaled between LAS files.
    const Rgb16* colors = cloud.stored_colors.data() + first;
    for (std::size_t i = 0; i < n; ++i) {
      std::memcpy(out + i * stride + *layout.color_offset, colors + i, 6);
    }
  } else if (layout.color_offset && cloud.hasColors()) {
    const Rgba8* colors = cloud.colors.data() + first;
    for (std::size_t i = 0; i < n; ++i) {
      // 8-bit colours (PLY uchar): LAS 1.4 R15 normalises colours to 16 bits; c * 257 maps 255
      // to 65535 exactly, and a LAS reader's value / 257 gives c back.
      std::uint16_t rgb[3] = {colorTo16Bits(colors[i].r), colorTo16Bits(colors[i].g),
                              colorTo16Bits(colors[i].b)};
      std::memcpy(out + i * stride + *layout.color_offset, rgb, 6);
    }
  } else if (layout.color_offset) {
    // A format with colour asked for (--point-format 3) where the cloud has none: black, as the
    // format's default; the reader of the cloud had no colour to keep.
    for (std::size_t i = 0; i < n; ++i) std::memset(out + i * stride + *layout.color_offset, 0, 6);
  }
  for (const RawTarget& target : layout.raws) {
    if (target.size == 0) {  // a normal component, stride 12
      for (std::size_t i = 0; i < n; ++i) {
        std::memcpy(out + i * stride + target.offset, target.source.data + (first + i) * 12, 4);
      }
      continue;
    }
    const std::byte* src = target.source.data + first * target.size;
    for (std::size_t i = 0; i < n; ++i) {
      std::memcpy(out + i * stride + target.offset, src + i * target.size, target.size);
    }
  }
  if (layout.return_number.data) {
    gather(layout.return_number, first, n, values.data());
    for (std::size_t i = 0; i < n; ++i) {
      int r = int(std::clamp(values[i], 0.0, 15.0));
      ++stats.by_return[std::size_t(r)];
    }
  }
}

std::vector<std::byte> vlrBytes(const LasVlr& vlr) {
  std::vector<std::byte> bytes(kLasVlrHeaderSize + vlr.data.size());
  std::memcpy(bytes.data() + 2, vlr.user_id.data(), std::min<std::size_t>(16, vlr.user_id.size()));
  storeLE(bytes.data() + 18, vlr.record_id);
  storeLE(bytes.data() + 20, std::uint16_t(vlr.data.size()));
  std::memcpy(bytes.data() + 22, vlr.description.data(),
              std::min<std::size_t>(32, vlr.description.size()));
  if (!vlr.data.empty()) std::memcpy(bytes.data() + 54, vlr.data.data(), vlr.data.size());
  return bytes;
}

bool hasExtraBytes(const Layout& layout) {
  return !layout.extra_types.empty() || !layout.source_extra_descriptors.empty();
}

// The source's descriptions as they were, then those of the columns added after them.
LasVlr extraBytesVlr(const Layout& layout) {
  LasVlr vlr{.user_id = "LASF_Spec", .record_id = 4, .description = "Extra Bytes Record"};
  vlr.data = layout.source_extra_descriptors;
  const std::size_t kept = vlr.data.size();
  vlr.data.resize(kept + layout.extra_types.size() * kLasExtraBytesDescriptorSize);
  for (std::size_t i = 0; i < layout.extra_types.size(); ++i) {
    std::byte* d = vlr.data.data() + kept + i * kLasExtraBytesDescriptorSize;
    const auto& [name, type] = layout.extra_types[i];
    d[2] = std::byte(extraDataType(type));
    std::memcpy(d + 4, name.data(), std::min<std::size_t>(32, name.size()));
  }
  return vlr;
}

}  // namespace

LasWritePlan planLasWrite(const PointCloud& cloud, const LasWriteOptions& options) {
  return makeLayout(cloud, options, cloud.count).plan;
}

LasWritePlan encodeLasRecords(const PointCloud& cloud, const LasWriteOptions& options,
                              std::byte* out) {
  const Layout layout = makeLayout(cloud, options, cloud.count);
  LasPointTotals stats;
  if (cloud.count > 0) encodeBlock(cloud, layout, 0, std::size_t(cloud.count), out, stats);
  return layout.plan;
}

std::optional<LasVlr> lasExtraBytesVlr(const PointCloud& cloud, const LasWriteOptions& options) {
  const Layout layout = makeLayout(cloud, options, cloud.count);
  if (!hasExtraBytes(layout)) return std::nullopt;
  return extraBytesVlr(layout);
}

LasWritePlan planLasWrite(const PointCloud& layout, const LasWriteOptions& options,
                          std::uint64_t point_count) {
  return makeLayout(layout, options, point_count).plan;
}

struct LasStreamWriter::State {
  LasWriteOptions options;
  Layout layout;  // of the layout cloud: the plan, the extra bytes' description
  std::uint64_t point_count = 0;
  Quantization quantization;
  std::size_t point_data_offset = 0;
  std::size_t vlr_count = 0;
  std::vector<const LasVlr*> evlrs;  // the source's, written after the points
  bool has_wkt = false;
  OutputFile out;
  std::optional<LazPointDataWriter> laz;
  LasPointTotals total;
  std::uint64_t written = 0;
  // Records of a batch, encoded in parallel blocks.
  std::vector<std::vector<std::byte>> buffers;
  std::vector<LasPointTotals> stats;

  State(const std::filesystem::path& path, const LasWriteOptions& write_options)
      : options(write_options), out(path) {}
};

LasStreamWriter::LasStreamWriter(const std::filesystem::path& path, const PointCloud& layout,
                                 std::uint64_t point_count, const LasWriteOptions& options)
    : state_(std::make_unique<State>(path, options)) {
  State& s = *state_;
  s.layout = makeLayout(layout, options, point_count);
  s.point_count = point_count;
  s.quantization = layout.quantization;
  const Layout& plan_layout = s.layout;
  const LasWritePlan& plan = plan_layout.plan;
  const bool v14 = plan.minor_version == 4;
  const std::size_t header_size = lasHeaderSizeFor(plan.minor_version);
  const LasHeader* src = s.options.source.get();

  // The source's VLRs in their order (its extra bytes description where it was), then the
  // records asked for that it does not have, then the extra bytes description if still due.
  std::vector<std::vector<std::byte>> vlrs;
  bool extra_bytes_written = false;
  auto isExtraBytes = [](const LasVlr& vlr) {
    return vlr.user_id == "LASF_Spec" && vlr.record_id == 4;
  };
  auto add = [&](const LasVlr& vlr) {
    s.has_wkt |= vlr.user_id == "LASF_Projection" && vlr.record_id == 2112;
    vlrs.push_back(vlrBytes(vlr));
  };
  if (src) {
    for (const LasVlr& vlr : src->vlrs) {
      if (!carriedLasRecord(vlr)) continue;
      if (vlr.extended) {
        if (v14) s.evlrs.push_back(&vlr);
      } else if (isExtraBytes(vlr)) {
        if (!hasExtraBytes(plan_layout) || extra_bytes_written) continue;
        LasVlr described = extraBytesVlr(plan_layout);
        described.description = vlr.description;
        add(described);
        extra_bytes_written = true;
      } else {
        add(vlr);
      }
    }
  }
  for (const LasVlr& vlr : s.options.vlrs) {
    if (vlr.data.size() > 65535 || isExtraBytes(vlr)) continue;
    const bool carried = src && std::any_of(src->vlrs.begin(), src->vlrs.end(), [&](const auto& v) {
                           return v.user_id == vlr.user_id && v.record_id == vlr.record_id;
                         });
    if (!carried) add(vlr);
  }
  if (hasExtraBytes(plan_layout) && !extra_bytes_written)
    vlrs.push_back(vlrBytes(extraBytesVlr(plan_layout)));
  const bool compress = options.laz_chunk_points > 0;
  laz::LaszipVlr laszip;
  if (compress) {
    laszip = makeLaszipVlr(plan.point_format, plan.record_length, options.laz_chunk_points);
    LasVlr vlr{.user_id = laz::kLaszipUserId,
               .record_id = laz::kLaszipRecordId,
               .description = "by Parallax"};
    vlr.data = laz::laszipVlrPayload(laszip);
    vlrs.push_back(vlrBytes(vlr));
  }
  s.point_data_offset = header_size;
  for (const auto& vlr : vlrs) s.point_data_offset += vlr.size();
  s.vlr_count = vlrs.size();

  const std::vector<std::byte> placeholder(header_size);
  s.out.write(placeholder.data(), placeholder.size());  // rewritten at the end: counts and bounds
  for (const auto& vlr : vlrs) s.out.write(vlr.data(), vlr.size());
  if (compress) s.laz.emplace(s.out, s.point_data_offset, laszip, options.progress);
}

LasStreamWriter::~LasStreamWriter() = default;

const LasWritePlan& LasStreamWriter::plan() const {
  return state_->layout.plan;
}

void LasStreamWriter::write(const PointCloud& batch) {
  State& s = *state_;
  assert(batch.quantization == s.quantization &&
         "every batch of a LAS file has the layout cloud's scale and offset");
  assert(s.written + batch.count <= s.point_count && "more points than the writer was told of");
  if (batch.count == 0) return;
  const Layout layout = makeLayout(batch, s.options, s.point_count, &s.layout.plan);
  assert(layout.plan.record_length == s.layout.plan.record_length &&
         "every batch of a LAS file has the layout cloud's columns");
  const std::size_t count = batch.count;
  const std::size_t stride = layout.plan.record_length;
  // Blocks encoded in parallel, a batch of blocks at a time, written in order.
  constexpr std::size_t kBlock = 1 << 16;
  constexpr std::size_t kBatch = 8;
  s.buffers.resize(kBatch);
  s.stats.resize(kBatch);
  for (std::size_t at = 0; at < count; at += kBlock * kBatch) {
    const std::size_t blocks = std::min(kBatch, (count - at + kBlock - 1) / kBlock);
    tbb::parallel_for(std::size_t(0), blocks, [&](std::size_t b) {
      const std::size_t first = at + b * kBlock;
      const std::size_t n = std::min(kBlock, count - first);
      s.buffers[b].resize(n * stride);
      s.stats[b] = LasPointTotals{};
      encodeBlock(batch, layout, first, n, s.buffers[b].data(), s.stats[b]);
    });
    for (std::size_t b = 0; b < blocks; ++b) {
      const std::size_t n = s.buffers[b].size() / stride;
      if (s.laz) {
        s.laz->add(s.buffers[b].data(), n);  // advances the progress as chunks are written
      } else {
        s.out.write(s.buffers[b].data(), s.buffers[b].size());
        if (s.options.progress) s.options.progress->advance(n);
      }
      s.total.merge(s.stats[b]);
    }
  }
  s.written += count;
}

void LasStreamWriter::finish() {
  State& s = *state_;
  assert(s.written == s.point_count && "fewer points than the writer was told of");
  const LasWritePlan& plan = s.layout.plan;
  const bool v14 = plan.minor_version == 4;
  const LasHeader* src = s.options.source.get();
  std::uint64_t end =
      s.laz ? s.laz->finish() : s.point_data_offset + s.written * std::uint64_t(plan.record_length);
  // The source's EVLRs after the points (LAS 1.4 R15 2.7), payloads as they were.
  const std::uint64_t evlr_offset = s.evlrs.empty() ? 0 : end;
  for (const LasVlr* vlr : s.evlrs) {
    std::byte head[kLasEvlrHeaderSize] = {};
    std::memcpy(head + 2, vlr->user_id.data(), std::min<std::size_t>(16, vlr->user_id.size()));
    storeLE(head + 18, vlr->record_id);
    storeLE(head + 20, std::uint64_t(vlr->data.size()));
    std::memcpy(head + 28, vlr->description.data(),
                std::min<std::size_t>(32, vlr->description.size()));
    s.out.write(head, sizeof head);
    if (!vlr->data.empty()) s.out.write(vlr->data.data(), vlr->data.size());
  }

  // The public header block.
  LasHeader fields;
  fields.version_minor = std::uint8_t(plan.minor_version);
  fields.file_source_id = src ? src->file_source_id : s.options.file_source_id;
  std::uint16_t encoding = s.options.gps_time_standard.value_or(false) ? 1 : 0;
  if (src) {
    // The source's bits, but the WKT bit, which belongs to 1.4 and is set below when due.
    encoding = std::uint16_t(src->global_encoding & ~16u);
    if (s.options.gps_time_standard) {
      encoding = std::uint16_t((encoding & ~1u) | (*s.options.gps_time_standard ? 1u : 0u));
    }
  }
  // Formats 6-10 require the WKT bit (R15 2.4); a copied GeoTIFF-keys CRS is a doubt left as is.
  if (v14 && (plan.point_format >= 6 || s.has_wkt || (src && (src->global_encoding & 16)))) {
    encoding |= 16;
  }
  fields.global_encoding = encoding;
  if (src) {
    fields.guid = src->guid;
    fields.system_identifier = src->system_identifier;
    fields.generating_software = src->generating_software;
    fields.creation_day = src->creation_day;
    fields.creation_year = src->creation_year;
  } else {
    stampGeneratedBy(fields);
  }
  fields.point_data_offset = std::uint32_t(s.point_data_offset);
  fields.vlr_count = std::uint32_t(s.vlr_count);
  fields.point_format = plan.point_format;
  fields.record_length = std::uint16_t(plan.record_length);
  fields.quantization = s.quantization;
  s.total.writeTo(fields, s.written);
  fields.evlr_offset = evlr_offset;
  fields.evlr_count = std::uint32_t(s.evlrs.size());
  const std::vector<std::byte> header = encodeLasHeader(fields, s.laz.has_value());
  s.out.writeAt(0, header.data(), header.size());
  s.out.commit();
}

void writeLas(const PointCloud& cloud, const std::filesystem::path& path,
              const LasWriteOptions& options) {
  LasStreamWriter writer(path, cloud, cloud.count, options);
  writer.write(cloud);
  writer.finish();
}

}  // namespace parallax
