// PointStream (convert_stages.h): one batch interface over the formats' chunk readers.
#include <type_traits>
#include <variant>

#include "core/error.h"
#include "io/las_reader.h"
#include "io/laz_reader.h"
#include "io/ply_reader.h"
#include "io/point_file.h"
#include "io/text_reader.h"
#include "lod/convert_stages.h"
#include "lod/in_memory_octree.h"

namespace parallax {

struct PointStream::State {
  struct WholeCloud {
    PointCloud cloud;
    std::uint64_t next = 0;
  };
  std::variant<PlyChunkReader, LasChunkReader, LazChunkReader, WholeCloud> reader;
};

namespace {

PointStream::State openStream(const std::filesystem::path& path,
                              const std::vector<std::string>& text_columns) {
  switch (detectPointFormat(path)) {
    case PointFormat::Ply:
      return {PlyChunkReader(path)};
    case PointFormat::Las:
      return {LasChunkReader(path)};
    case PointFormat::Laz:
      return {LazChunkReader(path)};
    case PointFormat::Text: {
      PointStream::State::WholeCloud whole;
      whole.cloud = readText(path, {.columns = text_columns});
      return {std::move(whole)};
    }
    default:
      // readPointFile gives the message for unknown formats.
      readPointFile(path);
      throw InputError({.file = path.string(), .expected = supportedFormatsText()});
  }
}

}  // namespace

PointStream::PointStream(const std::filesystem::path& path,
                         const std::vector<std::string>& text_columns)
    : state_(std::make_unique<State>(openStream(path, text_columns))) {}
PointStream::~PointStream() = default;

std::uint64_t PointStream::pointCount() const {
  return std::visit(
      [](const auto& r) -> std::uint64_t {
        if constexpr (std::is_same_v<std::decay_t<decltype(r)>, State::WholeCloud>) {
          return r.cloud.count;
        } else {
          return r.pointCount();
        }
      },
      state_->reader);
}

const Quantization& PointStream::quantization() const {
  return std::visit(
      [](const auto& r) -> const Quantization& {
        if constexpr (std::is_same_v<std::decay_t<decltype(r)>, State::WholeCloud>) {
          return r.cloud.quantization;
        } else {
          return r.quantization();
        }
      },
      state_->reader);
}

bool PointStream::next(PointCloud& batch, std::size_t max_points) {
  return std::visit(
      [&](auto& r) -> bool {
        if constexpr (std::is_same_v<std::decay_t<decltype(r)>, State::WholeCloud>) {
          const std::uint64_t n = std::min<std::uint64_t>(max_points, r.cloud.count - r.next);
          if (n == 0) {
            batch = PointCloud{};
            return false;
          }
          batch = slicePoints(r.cloud, r.next, n);
          r.next += n;
          return true;
        } else {
          return r.next(batch, max_points);
        }
      },
      state_->reader);
}

}  // namespace parallax
