#include "lod/copc_reader.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <cstring>
#include <map>
#include <mutex>

#include "core/byte_order.h"
#include "core/column_names.h"
#include "core/error.h"
#include "io/las_record_decoder.h"
#include "io/laz/layered_codec.h"
#include "io/laz/laz_layout.h"
#include "lod/copc_hierarchy.h"

namespace parallax {
namespace {

// Reads [offset, offset + out.size()) for `element`, a range past the end reported as the
// damaged or truncated COPC file it means (ByteSource::read's own check says less).
void readBytes(const ByteSource& in, std::uint64_t offset, std::span<std::byte> out,
               std::string_view element, std::stop_token cancel = {}) {
  if (offset > in.size() || out.size() > in.size() - offset) {
    throw InputError({.file = in.name(),
                      .byte_offset = offset,
                      .element = std::string(element),
                      .expected = std::to_string(out.size()) + " bytes inside the file (" +
                                  std::to_string(in.size()) + " bytes)",
                      .found = "a range that ends past it",
                      .hint = "the file is truncated, or its COPC hierarchy is damaged"});
  }
  in.read(offset, out, {.cancel = std::move(cancel), .element = element});
}

// Header and VLRs above this are not a COPC file's (real ones are a few kB; the WKT is the
// largest part).
constexpr std::uint64_t kMaxHeaderRegion = 64ull << 20;
constexpr std::uint64_t kMaxPointsPerByte = 4096;

[[noreturn]] void failFile(const std::string& file, std::optional<std::uint64_t> offset,
                           std::string element, std::string expected, std::string found,
                           std::string hint = {}) {
  throw InputError({.file = file,
                    .byte_offset = offset,
                    .element = std::move(element),
                    .expected = std::move(expected),
                    .found = std::move(found),
                    .hint = std::move(hint)});
}

// The header and VLRs, parsed from [0, point data offset) alone (the EVLRs are after the points:
// the hierarchy is read page by page instead). The parser sees no EVLRs; the header keeps their
// offset and count.
LasHeader readHeader(const ByteSource& in) {
  const std::string& file = in.name();
  if (in.size() < kCopcInfoPayloadOffset + kCopcInfoSize) {
    failFile(file, 0, "LAS header", "a COPC file (at least 589 bytes: header and info VLR)",
             std::to_string(in.size()) + " bytes");
  }
  std::array<std::byte, kCopcInfoPayloadOffset> head;
  readBytes(in, 0, head, "LAS header");
  if (!looksLikeCopc(head)) {
    const std::byte* vlr = head.data() + kCopcInfoVlrOffset;
    std::string user(reinterpret_cast<const char*>(vlr + 2), 16);
    user.resize(std::strlen(user.c_str()));
    failFile(file, kCopcInfoVlrOffset, "first VLR",
             "a LAS 1.4 file whose first VLR is the COPC info VLR (user id \"copc\", record 1)",
             hasLasSignature(head)
                 ? "LAS " + std::to_string(loadLE<std::uint8_t>(head.data() + 24)) + "." +
                       std::to_string(loadLE<std::uint8_t>(head.data() + 25)) + ", user id " +
                       quoteInput(user) + " there"
                 : std::string("no LAS signature"),
             "this is not a COPC file; open it as a LAZ file");
  }
  const std::uint32_t data_offset = loadLE<std::uint32_t>(head.data() + 96);
  if (data_offset < kCopcInfoPayloadOffset + kCopcInfoSize || data_offset > in.size() ||
      data_offset > kMaxHeaderRegion) {
    failFile(file, 96, "offset to point data",
             "an offset after the COPC info VLR (589) and inside the file (" +
                 std::to_string(in.size()) + " bytes)",
             std::to_string(data_offset));
  }
  std::vector<std::byte> region(data_offset);
  readBytes(in, 0, region, "LAS header and VLRs");
  const std::uint32_t evlr_count = loadLE<std::uint32_t>(region.data() + 243);
  std::memset(region.data() + 243, 0, 4);
  LasHeader header = parseLasHeader(region, file);
  header.evlr_count = evlr_count;
  return header;
}

void checkHeader(const LasHeader& header, const std::string& file) {
  if (header.version_major != 1 || header.version_minor != 4) {
    failFile(file, 24, "version", "LAS 1.4 (COPC 1.0)", header.versionString());
  }
  if (header.vlrs.empty() || header.vlrs[0].user_id != kCopcUserId ||
      header.vlrs[0].record_id != kCopcInfoRecordId) {
    failFile(file, kCopcInfoVlrOffset, "first VLR",
             "the COPC info VLR (user id \"copc\", record 1)",
             header.vlrs.empty() ? std::string("no VLR")
                                 : "user id " + quoteInput(header.vlrs[0].user_id) + ", record " +
                                       std::to_string(header.vlrs[0].record_id),
             "this is not a COPC file; open it as a LAZ file");
  }
  if (header.vlrs[0].data.size() != kCopcInfoSize) {
    failFile(file, kCopcInfoVlrOffset + 20, "COPC info VLR", "a payload of 160 bytes",
             std::to_string(header.vlrs[0].data.size()) + " bytes");
  }
  if (!header.laszip || header.laszip->compressor != 3) {
    failFile(file, 104, "point data format",
             "LAZ with layered chunks (compressor 3), as COPC requires",
             header.laszip ? "compressor " + std::to_string(header.laszip->compressor)
                           : std::string("uncompressed points"));
  }
  if (header.point_format < 6) {
    failFile(file, 104, "point data format", "point format 6, 7 or 8 (COPC 1.0)",
             "format " + std::to_string(header.point_format));
  }
  if (header.laszip->chunk_size != laz::kVariableChunkSize) {
    failFile(file, header.laszip_vlr_offset + 12, "laszip VLR chunk size",
             "a variable chunk size (one chunk per node)",
             std::to_string(header.laszip->chunk_size) + " points a chunk");
  }
}

CopcInfo checkInfo(const LasHeader& header, const std::string& file) {
  const CopcInfo info = parseCopcInfo(
      std::span<const std::byte, kCopcInfoSize>(header.vlrs[0].data.data(), kCopcInfoSize));
  const bool finite = std::isfinite(info.center[0]) && std::isfinite(info.center[1]) &&
                      std::isfinite(info.center[2]);
  if (!finite || !std::isfinite(info.halfsize) || !(info.halfsize > 0.0)) {
    failFile(file, kCopcInfoPayloadOffset, "COPC info VLR center and halfsize",
             "a finite center and a halfsize above 0", "halfsize " + std::to_string(info.halfsize));
  }
  if (!std::isfinite(info.spacing) || !(info.spacing > 0.0)) {
    failFile(file, kCopcInfoPayloadOffset + 32, "COPC info VLR spacing", "a spacing above 0",
             std::to_string(info.spacing));
  }
  return info;
}

// The LAZ chunk table: every chunk's offset, bytes and points, and where the chunks end.
CopcLimits readChunkTable(const ByteSource& in, const LasHeader& header) {
  const std::string& file = in.name();
  CopcLimits limits;
  limits.file = file;
  limits.file_size = in.size();
  limits.header_points = header.point_count;
  const std::uint64_t start = header.point_data_offset;
  auto read64 = [&](std::uint64_t at, const char* element) {
    std::array<std::byte, 8> bytes;
    readBytes(in, at, bytes, element);
    return loadLE<std::uint64_t>(bytes.data());
  };
  std::uint64_t table = read64(start, "LAZ chunk table offset");
  if (table == ~std::uint64_t(0)) table = read64(in.size() - 8, "LAZ chunk table offset");
  const std::uint64_t end =
      header.evlr_count > 0 && header.evlr_offset > table && header.evlr_offset <= in.size()
          ? header.evlr_offset
          : in.size();
  if (table < start + 8 || table > end || end - table < 8) {
    failFile(file, start, "LAZ chunk table offset",
             "the offset of a chunk table after the chunks (COPC needs the table)",
             std::to_string(std::int64_t(table)),
             "the file was not written to the end; a COPC writer always writes the table");
  }
  std::array<std::byte, 8> head;
  readBytes(in, table, head, "LAZ chunk table");
  const std::uint32_t version = loadLE<std::uint32_t>(head.data());
  const std::uint32_t count = loadLE<std::uint32_t>(head.data() + 4);
  if (version != 0 || count > (table - start - 8) || count > header.point_count) {
    failFile(file, table, "LAZ chunk table",
             "version 0 and at most one chunk per point and byte of chunk data",
             "version " + std::to_string(version) + ", " + std::to_string(count) + " chunks");
  }
  std::vector<std::byte> stream(
      std::size_t(std::min<std::uint64_t>(end - table - 8, 16ull * count + 64)));
  readBytes(in, table + 8, stream, "LAZ chunk table");
  std::vector<std::uint32_t> points, bytes;
  if (!laz::decodeChunkTable(stream, count, true, points, bytes)) {
    failFile(file, table + 8, "LAZ chunk table", "a table of " + std::to_string(count) + " chunks",
             "a stream that ends early (truncated or corrupt)");
  }
  std::uint64_t offset = start + 8, total = 0;
  limits.chunks.reserve(count);
  for (std::uint32_t i = 0; i < count; ++i) {
    if (bytes[i] > table - offset) {
      failFile(file, table, "LAZ chunk table, chunk " + std::to_string(i),
               "a chunk ending before the chunk table at byte " + std::to_string(table),
               std::to_string(bytes[i]) + " bytes at byte " + std::to_string(offset));
    }
    // What a lying count could make a node's load allocate is capped as the LAZ reader caps it
    // (io/laz_source.cpp: a point costs at least ~0.006 bits, 4096 points a byte is twice that).
    if (points[i] > 0 && (bytes[i] < header.record_length ||
                          points[i] > 1 + kMaxPointsPerByte * (bytes[i] - header.record_length))) {
      failFile(file, table, "LAZ chunk table, chunk " + std::to_string(i),
               "enough bytes for " + std::to_string(points[i]) + " points",
               std::to_string(bytes[i]) + " bytes at byte " + std::to_string(offset));
    }
    // A chunk of no bytes holds no points and cannot be a node's (two would share an offset).
    if (bytes[i] > 0) limits.chunks[offset] = {bytes[i], points[i], i};
    offset += bytes[i];
    total += points[i];
  }
  if (total != header.point_count) {
    failFile(file, table, "LAZ chunk table",
             "chunks holding the header's " + std::to_string(header.point_count) + " points",
             std::to_string(total) + " points in " + std::to_string(count) + " chunks");
  }
  limits.chunk_count = count;
  limits.data_begin = start;
  limits.data_end = table + 8 + stream.size();
  return limits;
}

class CopcOctree final : public Octree {
 public:
  explicit CopcOctree(std::unique_ptr<ByteSource> source) : in_(std::move(source)) {
    const std::string& file = in_->name();
    header_ = readHeader(*in_);
    checkHeader(header_, file);
    info_vlr_ = checkInfo(header_, file);
    CopcLimits limits = readChunkTable(*in_, header_);
    limits.cube = info_vlr_.cube();
    limits.spacing = info_vlr_.spacing;
    hierarchy_ = std::make_unique<CopcHierarchy>(std::move(limits));
    hierarchy_->addRoot(info_vlr_.root_hierarchy_offset, info_vlr_.root_hierarchy_size, nodes_);
    items_ = header_.laszip->items;
    try {
      releaseDecoder(laz::makeLayeredDecoder(items_));
    } catch (const laz::UnsupportedItems& e) {
      failFile(file, header_.laszip_vlr_offset, "laszip VLR",
               "LAZ items Parallax decodes (layered, formats 6-10)", e.what());
    }
    plan_ = makeLasDecodePlan(header_);
    if (header_.record_length != header_.laszip->recordLength()) {
      failFile(file, header_.laszip_vlr_offset, "laszip VLR",
               "items of the header's record length (" + std::to_string(header_.record_length) +
                   " bytes)",
               std::to_string(header_.laszip->recordLength()) + " bytes");
    }
    expandHierarchy(0);
    describe();
  }

  const OctreeInfo& info() const override { return info_; }
  std::span<const OctreeNode> nodes() const override { return nodes_; }

  void expandHierarchy(std::int32_t index) override {
    assert(index >= 0 && std::size_t(index) < nodes_.size() && "expandHierarchy: no such node");
    const OctreeNode& node = nodes_[std::size_t(index)];
    if (!node.hierarchy_pending) return;
    const std::vector<std::byte> page = pageOf(node, {});
    {
      const std::lock_guard lock(pages_mutex_);
      pages_.erase(node.byte_offset);  // read into nodes(): not needed again
    }
    hierarchy_->readPage(page, index, nodes_);
  }

  // Over a network, a child page is fetched on a loader thread (fetchHierarchy) and kept until
  // the frame loop's expandHierarchy() takes it, so that the frame loop never waits.
  bool hierarchyReady(std::int32_t index) const override {
    const OctreeNode& node = nodes_[std::size_t(index)];
    if (!node.hierarchy_pending || in_->local()) return true;
    const std::lock_guard lock(pages_mutex_);
    return pages_.count(node.byte_offset) > 0;
  }

  void fetchHierarchy(const OctreeNode& node, std::stop_token cancel) const override {
    if (!node.hierarchy_pending || in_->local()) return;
    std::vector<std::byte> page = pageOf(node, std::move(cancel));
    const std::lock_guard lock(pages_mutex_);
    pages_[node.byte_offset] = std::move(page);
  }

  // The chunks of the nodes named, and the pages of the pending ones, as one hint to a source
  // with latency (which merges adjacent ranges: a level's chunks are written side by side).
  void prefetch(std::span<const OctreeNode> nodes,
                std::span<const OctreeNode> hierarchy) const override {
    if (in_->local()) return;
    std::vector<ByteRange> ranges;
    for (const OctreeNode& node : nodes) {
      if (!node.hierarchy_pending && node.byte_size > 0) {
        ranges.push_back({node.byte_offset, node.byte_size});
      }
    }
    {
      const std::lock_guard lock(pages_mutex_);
      for (const OctreeNode& node : hierarchy) {
        if (node.hierarchy_pending && !pages_.count(node.byte_offset)) {
          ranges.push_back({node.byte_offset, node.byte_size});
        }
      }
    }
    in_->prefetch(ranges);
  }

  PointCloud loadNode(const OctreeNode& node) const override {
    return loadNodeCancellable(node, {});
  }

  PointCloud loadNodeCancellable(const OctreeNode& node, std::stop_token cancel) const override {
    std::uint64_t offset = node.byte_offset, bytes = node.byte_size;
    std::uint32_t count = node.point_count;
    if (node.hierarchy_pending) {
      const std::vector<std::byte> page = pageOf(node, cancel);
      const CopcEntry entry = hierarchy_->ownEntry(page, node);
      offset = entry.offset;
      bytes = std::uint64_t(entry.byte_size);
      count = std::uint32_t(entry.point_count);
    }
    return decodeChunk(node.name, offset, bytes, count, plan_, cancel);
  }

  PointCloud loadNodeWhole(const OctreeNode& node) const override {
    std::uint64_t offset = node.byte_offset, bytes = node.byte_size;
    std::uint32_t count = node.point_count;
    if (node.hierarchy_pending) {
      const CopcEntry entry = hierarchy_->ownEntry(pageOf(node, {}), node);
      offset = entry.offset;
      bytes = std::uint64_t(entry.byte_size);
      count = std::uint32_t(entry.point_count);
    }
    return decodeChunk(node.name, offset, bytes, count, whole_plan_, {});
  }

  void selectAttributes(const AttributeSelection& attributes) override {
    const bool colors_8bit = plan_.colors_8bit;
    plan_ = makeLasDecodePlan(header_, attributes);
    plan_.colors_8bit = colors_8bit;  // the file's rule, decided at opening
    // (whole_plan_ never changes after opening: loader threads and loadNodeWhole() read it.)
    describeColumns();
  }

  CopcDetails details() const {
    return {.file = in_->name(),
            .file_bytes = in_->size(),
            .header = header_,
            .info = info_vlr_,
            .chunks = hierarchy_->limits().chunk_count,
            .pages_read = hierarchy_->pagesRead(),
            .pending_nodes = hierarchy_->pendingNodes()};
  }

 private:
  // The hierarchy page a pending node points at: fetched before (fetchHierarchy), or read now.
  std::vector<std::byte> pageOf(const OctreeNode& node, std::stop_token cancel) const {
    {
      const std::lock_guard lock(pages_mutex_);
      const auto it = pages_.find(node.byte_offset);
      if (it != pages_.end() && it->second.size() == node.byte_size) return it->second;
    }
    std::vector<std::byte> page(node.byte_size);
    readBytes(*in_, node.byte_offset, page, "hierarchy page of node " + node.name,
              std::move(cancel));
    return page;
  }

  // The raw LAS records of a node's chunk.
  // Only the LAZ layers of `fields` (laz::fields::k*) are decoded.
  ByteBuffer decodeRecords(const std::string& name, std::uint64_t offset, std::uint64_t bytes,
                           std::uint32_t count, std::uint32_t fields,
                           std::stop_token cancel) const {
    const std::string element = "node " + name + " (its LAZ chunk)";
    std::vector<std::byte> compressed(bytes);
    readBytes(*in_, offset, compressed, element, std::move(cancel));
    ByteBuffer records(std::size_t(count) * header_.record_length);
    std::unique_ptr<laz::ChunkDecoder> decoder = takeDecoder(fields);
    try {
      decoder->decode(compressed, count, records.data());
    } catch (const laz::ChunkCorrupt& e) {
      releaseDecoder(std::move(decoder));  // it resets at the next chunk
      failFile(in_->name(), offset, element,
               std::to_string(count) + " points, as the hierarchy says, in " +
                   std::to_string(bytes) + " bytes",
               "a chunk that does not decode from its point " + std::to_string(e.point()) + ": " +
                   e.what(),
               "the file is damaged (truncated or altered)");
    }
    releaseDecoder(std::move(decoder));
    return records;
  }

  // A node's points, with `plan`'s columns (plan_ or whole_plan_).
  PointCloud decodeChunk(const std::string& name, std::uint64_t offset, std::uint64_t bytes,
                         std::uint32_t count, const LasDecodePlan& plan,
                         std::stop_token cancel) const {
    PointCloud cloud = allocateLasCloud(header_, plan, count);
    cloud.source.color = plan.colors_8bit ? ScalarType::UInt8 : ScalarType::UInt16;
    if (count == 0) return cloud;
    const ByteBuffer records =
        decodeRecords(name, offset, bytes, count, plan.laz_fields, std::move(cancel));
    LasDecodeStats stats;
    decodeLasRecords(records.data(), count, plan, cloud, 0, stats);
    cloud.bounds = stats.world(cloud.quantization);
    return cloud;
  }

  std::unique_ptr<laz::ChunkDecoder> pooledDecoder() const {
    {
      const std::lock_guard lock(decoders_mutex_);
      if (!decoders_.empty()) {
        auto decoder = std::move(decoders_.back());
        decoders_.pop_back();
        return decoder;
      }
    }
    return laz::makeLayeredDecoder(items_);
  }
  // A decoder reading only the layers of `fields`.
  std::unique_ptr<laz::ChunkDecoder> takeDecoder(std::uint32_t fields) const {
    std::unique_ptr<laz::ChunkDecoder> decoder = pooledDecoder();
    decoder->selectFields(fields);
    return decoder;
  }
  void releaseDecoder(std::unique_ptr<laz::ChunkDecoder> decoder) const {
    const std::lock_guard lock(decoders_mutex_);
    decoders_.push_back(std::move(decoder));
  }

  void describe() {
    // The colour rule, from the root's points (see copc_reader.h).
    if (plan_.color_offset) {
      const OctreeNode& root = nodes_[0];
      plan_.colors_8bit =
          root.point_count > 0 &&
          !lasColorsAbove255(decodeRecords(root.name, root.byte_offset, root.byte_size,
                                           root.point_count, plan_.laz_fields, {})
                                 .data(),
                             root.point_count, plan_);
    }
    info_.point_count = header_.point_count;
    info_.cube = info_vlr_.cube();
    info_.bounds = header_.bounds;
    const bool bounds_ok =
        std::isfinite(info_.bounds.min[0]) && std::isfinite(info_.bounds.max[0]) &&
        info_.bounds.min[0] <= info_.bounds.max[0] && info_.bounds.min[1] <= info_.bounds.max[1] &&
        info_.bounds.min[2] <= info_.bounds.max[2];
    if (!bounds_ok) info_.bounds = info_.cube;  // a header without bounds: the cube will do
    info_.quantization = header_.quantization;
    info_.spacing = info_vlr_.spacing;
    whole_plan_ = plan_;  // (every column: selectAttributes() has not been called yet)
    describeColumns();
  }

  // What info() says of the columns loadNode() gives (plan_'s).
  void describeColumns() {
    // One point: empty columns would read as absent attributes.
    const PointCloud prototype = allocateLasCloud(header_, plan_, 1);
    info_.attributes = prototype.attributeNames();
    info_.has_colors = prototype.hasColors();
    info_.has_normals = prototype.hasNormals();
    info_.has_intensity = prototype.hasIntensity();
    // The info VLR's GPS time range (COPC 1.0), where the file has points with GPS time.
    info_.gps_time_range.reset();
    if (prototype.findScalar(column_names::kGpsTime) && header_.point_count > 0 &&
        info_vlr_.gps_time_min <= info_vlr_.gps_time_max) {
      info_.gps_time_range = {{info_vlr_.gps_time_min, info_vlr_.gps_time_max}};
    }
    info_.has_classification = prototype.hasClassification();
  }

  std::unique_ptr<ByteSource> in_;
  LasHeader header_;
  CopcInfo info_vlr_;
  std::unique_ptr<CopcHierarchy> hierarchy_;
  std::vector<laz::LazItem> items_;
  LasDecodePlan plan_;        // the columns loadNode() gives (selectAttributes)
  LasDecodePlan whole_plan_;  // every column, for loadNodeWhole()
  OctreeInfo info_;
  std::vector<OctreeNode> nodes_;
  mutable std::mutex decoders_mutex_;
  mutable std::vector<std::unique_ptr<laz::ChunkDecoder>> decoders_;
  // Hierarchy pages fetched by loader threads for the frame loop (by their byte offset).
  mutable std::mutex pages_mutex_;
  mutable std::map<std::uint64_t, std::vector<std::byte>> pages_;
};

}  // namespace

bool looksLikeCopc(std::span<const std::byte> head) {
  if (head.size() < kCopcInfoPayloadOffset || !hasLasSignature(head)) return false;
  const std::byte* p = head.data();
  if (loadLE<std::uint8_t>(p + 24) != 1 || loadLE<std::uint8_t>(p + 25) != 4) return false;
  const std::byte* vlr = p + kCopcInfoVlrOffset;
  char user[17] = {};
  std::memcpy(user, vlr + 2, 16);
  return std::strcmp(user, kCopcUserId) == 0 &&
         loadLE<std::uint16_t>(vlr + 18) == kCopcInfoRecordId;
}

bool isCopcFile(const std::filesystem::path& path) {
  std::error_code error;
  if (!std::filesystem::is_regular_file(path, error)) return false;
  try {
    const auto source = openFileSource(path);
    if (source->size() < kCopcInfoPayloadOffset) return false;
    std::array<std::byte, kCopcInfoPayloadOffset> head;
    readBytes(*source, 0, head, "LAS header");
    return looksLikeCopc(head);
  } catch (const std::exception&) {
    return false;
  }
}

std::unique_ptr<Octree> openCopc(const std::filesystem::path& path) {
  return openCopc(openFileSource(path));
}

std::unique_ptr<Octree> openCopc(std::unique_ptr<ByteSource> source) {
  return std::make_unique<CopcOctree>(std::move(source));
}

std::unique_ptr<Octree> openCopcFromMemory(std::vector<std::byte> bytes, const std::string& name) {
  return openCopc(makeMemorySource(std::move(bytes), name));
}

std::optional<CopcDetails> copcDetails(const Octree& octree) {
  const auto* copc = dynamic_cast<const CopcOctree*>(&octree);
  if (!copc) return std::nullopt;
  return copc->details();
}

}  // namespace parallax
