// Reading text point files: the layout (text_layout.h), then the body in blocks of whole lines
// (text_decoder.h), whole (readText) or in chunks (TextChunkReader).
//
// The flow of readText:
//   1. detect the layout from the first lines;
//   2. one parallel pass over the bytes: cut the body into blocks, count each block's points,
//      and parse the positions of about 4096 evenly spread lines (every line of a small file);
//   3. choose the quantization from that sample and allocate the columns;
//   4. parse every block in parallel straight into the columns, positions quantized as they are
//      read, noting the exact bounds and decimals of every position;
//   5. check the quantization against them: kept, shifted by whole offsets, or (the sample missed
//      a longer decimal or an outlier) the positions parsed again with the exact choice.
// The input's pages are released as each pass leaves them, so the peak is the columns plus the
// blocks being parsed.
#include "io/text_reader.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cassert>
#include <exception>
#include <stdexcept>

#include "core/error.h"
#include "io/bytes_as_text.h"
#include "io/mapped_file.h"
#include "io/text_decoder.h"
#include "io/text_layout.h"

namespace parallax {
namespace {

using text::Block;
using text::BodyPlan;
using text::ParseResult;
using text::PositionStats;

template <class F>
void forEachBlock(bool parallel, std::size_t count, F&& body) {
  if (parallel) {
    tbb::parallel_for(std::size_t(0), count, body);
  } else {
    for (std::size_t i = 0; i < count; ++i) body(i);
  }
}

void releaseBlock(const MappedFile* file, const Block& block) {
  if (file != nullptr) file->releaseRead(block.begin, block.end - block.begin);
}

// The parse found other points than the count: the two passes disagree on which lines are
// points, a bug (the columns were sized by the count).
void checkBlockCount(const ParseResult& result, const Block& block) {
  if (result.points != block.points) {
    throw std::logic_error("text reader: a block parsed " + std::to_string(result.points) +
                           " points where its lines counted " + std::to_string(block.points));
  }
}

// Parses every block into `cloud` (positions in cloud.quantization) and returns the positions'
// stats; the first bad line in the file is thrown.
PositionStats decodeBlocks(std::string_view bytes, const BodyPlan& plan, const text::Layout& layout,
                           const std::string& file, PointCloud& cloud, bool positions_only,
                           const MappedFile* mapping, bool parallel, Progress* progress) {
  std::vector<PositionStats> stats(plan.blocks.size());
  std::vector<std::exception_ptr> errors(plan.blocks.size());
  forEachBlock(parallel, plan.blocks.size(), [&](std::size_t b) {
    const Block& block = plan.blocks[b];
    try {
      const ParseResult result = text::parseLines(bytes, block.begin, block.end, block.first_line,
                                                  block.points, layout, file,
                                                  {.cloud = &cloud,
                                                   .first_index = block.first_point,
                                                   .quantization = &cloud.quantization,
                                                   .positions_only = positions_only});
      checkBlockCount(result, block);
      stats[b] = result.stats;
    } catch (...) {
      errors[b] = std::current_exception();
    }
    releaseBlock(mapping, block);
    if (progress) progress->advance(block.end - block.begin);
  });
  for (const auto& error : errors) {
    if (error) std::rethrow_exception(error);  // the first in the file
  }
  PositionStats all;
  for (const PositionStats& s : stats) all.merge(s);
  return all;
}

// Every position seen (a small file): the exact choice, which the check after the parse keeps.
text::SampledQuantization firstQuantization(const BodyPlan& plan) {
  return plan.exact ? text::exactTextChoice(plan.sample)
                    : text::sampledTextQuantization(plan.sample);
}

PointCloud readAll(std::string_view bytes, const std::string& file, const TextReadOptions& options,
                   const MappedFile* mapping) {
  const text::Layout layout = text::detectLayout(bytes, file, options.columns, options.pts);
  // Progress is by bytes: the header's count too, so that the whole file adds up to its size.
  if (options.progress) options.progress->advance(std::min(layout.body_offset, bytes.size()));
  const BodyPlan plan = text::planBody(bytes, layout, file, mapping, options.parallel);
  const text::SampledQuantization used = firstQuantization(plan);
  PointCloud cloud = text::allocateTextCloud(layout, plan.points);
  cloud.quantization = used.quantization;
  const PositionStats exact = decodeBlocks(bytes, plan, layout, file, cloud, false, mapping,
                                           options.parallel, options.progress);
  const text::RequantizePlan check = text::planRequantize(used, exact);
  switch (check.action) {
    case text::Requantize::None:
      break;
    case text::Requantize::Shift:
      text::shiftPositions(cloud, check.final, options.parallel);
      break;
    case text::Requantize::Decode:
      cloud.quantization = check.final;
      decodeBlocks(bytes, plan, layout, file, cloud, true, mapping, options.parallel, nullptr);
      break;
  }
  cloud.computeBounds();
  return cloud;
}

}  // namespace

PointCloud readText(const std::filesystem::path& path, const TextReadOptions& options) {
  MappedFile file(path);
  file.adviseSequential(0, file.size());
  return readAll(bytesAsText(file.bytes()), file.path(), options, &file);
}

PointCloud readTextFromMemory(std::span<const std::byte> bytes, const std::string& name,
                              const TextReadOptions& options) {
  return readAll(bytesAsText(bytes), name, options, nullptr);
}

std::uint64_t countTextPoints(const std::filesystem::path& path, const TextReadOptions& options) {
  MappedFile file(path);
  file.adviseSequential(0, file.size());
  const std::string_view bytes = bytesAsText(file.bytes());
  const text::Layout layout = text::detectLayout(bytes, file.path(), options.columns, options.pts);
  return text::planBody(bytes, layout, file.path(), &file, options.parallel).points;
}

bool looksLikeTextPoints(std::span<const std::byte> bytes) {
  const std::string_view head = bytesAsText(bytes).substr(0, 64 << 10);
  return text::looksLikeTextPoints(head, bytes.size() > head.size());
}

// ---------------------------------------------------------------------------------------------
// Streaming

struct TextChunkReader::State {
  State(const std::filesystem::path& path, const TextReadOptions& options,
        const Quantization* given)
      : file(path),
        bytes(bytesAsText(file.bytes())),
        layout(text::detectLayout(bytes, file.path(), options.columns, options.pts)),
        plan(text::planBody(bytes, layout, file.path(), &file, true)) {
    if (given != nullptr) {
      quantization = *given;
    } else if (plan.exact) {
      quantization = text::exactTextQuantization(plan.sample);
    } else {
      // The positions alone, every line, for their exact stats. A bad line is left to the chunk
      // that holds it, so errors come in file order with the points before them delivered.
      std::vector<PositionStats> stats(plan.blocks.size());
      tbb::parallel_for(std::size_t(0), plan.blocks.size(), [&](std::size_t b) {
        const Block& block = plan.blocks[b];
        try {
          stats[b] = text::parseLines(bytes, block.begin, block.end, block.first_line, block.points,
                                      layout, file.path(), {.positions_only = true})
                         .stats;
        } catch (const InputError&) {
        }
        releaseBlock(&file, block);
      });
      PositionStats all;
      for (const PositionStats& s : stats) all.merge(s);
      quantization = text::exactTextQuantization(all);
    }
  }

  MappedFile file;
  std::string_view bytes;
  text::Layout layout;
  BodyPlan plan;
  Quantization quantization;
  // Where the next chunk starts: inside plan.blocks[next_block], after `done_in_block` points,
  // at byte `cursor` and line `cursor_line`.
  std::size_t next_block = 0;
  std::uint64_t done_in_block = 0;
  std::size_t cursor = 0;
  std::uint64_t cursor_line = 0;
  std::uint64_t delivered = 0;
};

TextChunkReader::TextChunkReader(const std::filesystem::path& path, const TextReadOptions& options,
                                 const Quantization* quantization)
    : state_(std::make_unique<State>(path, options, quantization)) {}
TextChunkReader::~TextChunkReader() = default;
TextChunkReader::TextChunkReader(TextChunkReader&&) noexcept = default;

std::uint64_t TextChunkReader::pointCount() const {
  return state_->plan.points;
}

const Quantization& TextChunkReader::quantization() const {
  return state_->quantization;
}

bool TextChunkReader::next(PointCloud& chunk, std::size_t max_points) {
  assert(max_points > 0 && "TextChunkReader::next needs a positive max_points");
  State& s = *state_;
  const std::uint64_t remaining = s.plan.points - s.delivered;
  if (remaining == 0) {
    chunk = PointCloud{};
    return false;
  }
  const std::uint64_t n = std::min<std::uint64_t>(max_points, remaining);
  chunk = text::allocateTextCloud(s.layout, n);
  chunk.quantization = s.quantization;

  // The pieces of blocks this chunk covers; each starts at a known byte and line.
  struct Piece {
    std::size_t begin, end;
    std::uint64_t first_line, count, dst;
  };
  std::vector<Piece> pieces;
  std::uint64_t filled = 0;
  std::size_t index = s.next_block;
  std::uint64_t skip = s.done_in_block;
  while (filled < n) {
    const Block& block = s.plan.blocks[index];
    const std::uint64_t available = block.points - skip;
    const std::uint64_t take = std::min(available, n - filled);
    if (take > 0) {
      pieces.push_back({skip > 0 ? s.cursor : block.begin, block.end,
                        skip > 0 ? s.cursor_line : block.first_line, take, filled});
    }
    filled += take;
    if (take == available) {
      ++index;
      skip = 0;
    } else {
      skip += take;
    }
  }
  std::vector<ParseResult> results(pieces.size());
  std::vector<std::exception_ptr> errors(pieces.size());
  tbb::parallel_for(std::size_t(0), pieces.size(), [&](std::size_t i) {
    const Piece& piece = pieces[i];
    try {
      results[i] = text::parseLines(s.bytes, piece.begin, piece.end, piece.first_line, piece.count,
                                    s.layout, s.file.path(),
                                    {.cloud = &chunk,
                                     .first_index = piece.dst,
                                     .quantization = &chunk.quantization,
                                     .positions_only = false});
    } catch (...) {
      errors[i] = std::current_exception();
    }
  });
  for (const auto& error : errors) {
    if (error) std::rethrow_exception(error);  // the first in the file
  }
  PositionStats stats;
  for (std::size_t i = 0; i < pieces.size(); ++i) {
    if (results[i].points != pieces[i].count) {
      throw std::logic_error("text chunk reader: a piece parsed " +
                             std::to_string(results[i].points) +
                             " points where its lines counted " + std::to_string(pieces[i].count));
    }
    stats.merge(results[i].stats);
  }
  // The chunk's input is read: its pages leave the resident set (the page cache keeps them).
  s.file.releaseRead(pieces.front().begin, results.back().end - pieces.front().begin);
  if (stats.outside[0] || stats.outside[1] || stats.outside[2]) {
    throw InputError({.file = s.file.path(),
                      .line = pieces.front().first_line,
                      .property = "x, y, z",
                      .expected = "points inside the streaming quantization's range",
                      .found = "a point outside it in points " + std::to_string(s.delivered) +
                               " to " + std::to_string(s.delivered + n - 1),
                      .hint = "the quantization given to the reader does not cover the file"});
  }
  s.next_block = index;
  s.done_in_block = skip;
  if (skip > 0) {
    s.cursor = results.back().end;
    s.cursor_line = pieces.back().first_line + results.back().lines;
  }
  s.delivered += n;
  chunk.computeBounds();
  return true;
}

}  // namespace parallax
