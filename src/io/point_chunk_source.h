// The one interface every format's streaming reader implements: a file's points handed out in
// chunks, in file order, holding one chunk at a time, so that files larger than memory flow
// through the out-of-core octree builder (lod/convert_stages.h: PointStream) with bounded memory.
// A format's row in the table (point_format.h) opens one with `open_chunks`.
#pragma once

#include <cstddef>
#include <cstdint>

#include "core/point_cloud.h"
#include "core/quantization.h"
#include "io/coordinate_system.h"

namespace parallax {

class PointChunkSource {
 public:
  virtual ~PointChunkSource() = default;

  // The points the file holds (its header's count, or a counting pass's).
  virtual std::uint64_t pointCount() const = 0;
  // The integer grid every chunk's positions are on; fixed before the first chunk.
  virtual const Quantization& quantization() const = 0;
  // The file's coordinate reference system; empty for formats that state none.
  virtual const CoordinateSystem& crs() const;

  // Replaces `chunk` with the next at most `max_points` points (at least one); false (and an
  // empty chunk) at the end. `max_points` must be positive.
  virtual bool next(PointCloud& chunk, std::size_t max_points) = 0;

  // Whether skip() can step over points without decoding what comes before them (records of
  // known size or ranges of known start): the builder's tasks then read points [first, last) of
  // one file each. Formats that cannot go back to settle something (LAZ's colour depth, a text
  // file's lines) answer false and are read whole by one task.
  virtual bool canSkip() const { return false; }
  // Steps over the next `count` points (fewer at the end) without handing them out. Only where
  // canSkip(); the default asserts.
  virtual void skip(std::uint64_t count);
};

}  // namespace parallax
