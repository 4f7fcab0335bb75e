// PointStream (convert_stages.h): one batch interface over the formats' chunk readers.
#include <variant>

#include "core/error.h"
#include "io/las_reader.h"
#include "io/laz_reader.h"
#include "io/ply_reader.h"
#include "io/point_file.h"
#include "io/text_reader.h"
#include "lod/convert_stages.h"

namespace parallax {

struct PointStream::State {
  std::variant<PlyChunkReader, LasChunkReader, LazChunkReader, TextChunkReader> reader;
  CoordinateSystem crs;
};

namespace {

PointStream::State openStream(const std::filesystem::path& path,
                              const std::vector<std::string>& text_columns,
                              const Quantization* quantization) {
  switch (detectPointFormat(path)) {
    case PointFormat::Ply: {
      PlyChunkReader reader(path);
      if (quantization) reader.setQuantization(*quantization);
      return {std::move(reader)};
    }
    case PointFormat::Las:
      return {LasChunkReader(path)};  // the header's quantization, whatever is asked
    case PointFormat::Laz:
      return {LazChunkReader(path)};  // likewise
    case PointFormat::Text:
      return {TextChunkReader(path, {.columns = text_columns}, quantization)};
    default:
      // readPointFile gives the message for unknown formats.
      readPointFile(path);
      throw InputError({.file = path.string(), .expected = supportedFormatsText()});
  }
}

}  // namespace

PointStream::PointStream(const std::filesystem::path& path,
                         const std::vector<std::string>& text_columns,
                         const Quantization* quantization)
    : state_(std::make_unique<State>(openStream(path, text_columns, quantization))) {
  if (const auto* las = std::get_if<LasChunkReader>(&state_->reader)) {
    state_->crs = coordinateSystemOf(las->header());
  } else if (const auto* laz = std::get_if<LazChunkReader>(&state_->reader)) {
    state_->crs = coordinateSystemOf(laz->header());
  }
}
PointStream::~PointStream() = default;

std::uint64_t PointStream::pointCount() const {
  return std::visit([](const auto& r) { return r.pointCount(); }, state_->reader);
}

const Quantization& PointStream::quantization() const {
  return std::visit([](const auto& r) -> const Quantization& { return r.quantization(); },
                    state_->reader);
}

const CoordinateSystem& PointStream::crs() const {
  return state_->crs;
}

bool PointStream::next(PointCloud& batch, std::size_t max_points) {
  return std::visit([&](auto& r) { return r.next(batch, max_points); }, state_->reader);
}

}  // namespace parallax
