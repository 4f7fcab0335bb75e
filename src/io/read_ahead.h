// Reading ahead of a reader that knows the ranges it will read, in their order (a LAS file's
// blocks of records, a LAZ file's chunks): a source with latency (HTTP, core/byte_source.h) is
// told the next ones through ByteSource::prefetch while the reader decodes the ones it has, so a
// stream of a remote file costs a few large requests in flight rather than one round trip a
// block. The hint is a window: a fixed number of unfinished ranges from the first unfinished
// one, so the bytes fetched ahead of the decode stay bounded (the window times the range size).
//
// Ranges must be read exactly as planned: an HTTP source serves a read from a hinted range only
// when offset and size are the same.
#pragma once

#include <cstddef>
#include <mutex>
#include <span>
#include <vector>

#include "core/byte_source.h"

namespace parallax {

class ReadAhead {
 public:
  // `plan`: the ranges in the order they will (mostly) be read; `window`: how many unfinished
  // ranges are hinted at once (at least 1). Does nothing for a local source (the kernel reads
  // ahead of pread on its own) or a plan of one range.
  ReadAhead(const ByteSource& in, std::vector<ByteRange> plan, std::size_t window);

  // Call (any thread) when plan[index] has been read: once the first unfinished range moves,
  // the hint moves on to the window from there. (The constructor hints the first window.)
  void finished(std::size_t index);

 private:
  void hint();  // with mutex_ held

  const ByteSource& in_;
  std::vector<ByteRange> plan_;
  std::size_t window_;
  bool active_;
  std::mutex mutex_;
  std::vector<bool> done_;
  std::size_t first_open_ = 0;  // no range before it is unfinished
  std::size_t hinted_from_ = std::size_t(-1);
};

}  // namespace parallax
