#include "lod/copc_writer.h"

#include <tbb/enumerable_thread_specific.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>

#include "core/byte_order.h"
#include "io/las_writer.h"
#include "io/laz/layered_codec.h"
#include "io/laz/laz_layout.h"
#include "io/laz_writer.h"
#include "io/point_file.h"
#include "lod/copc_format.h"
#include "lod/octree_build_options.h"
#include "lod/octree_node_batches.h"

namespace parallax {
namespace {

std::vector<std::byte> vlrBytes(const std::string& user_id, std::uint16_t record_id,
                                const std::string& description,
                                std::span<const std::byte> payload) {
  if (payload.size() > 65535) {
    throw std::runtime_error("COPC writer: a VLR of " + std::to_string(payload.size()) +
                             " bytes is over LAS's 65 535");
  }
  std::vector<std::byte> bytes(kLasVlrHeaderSize + payload.size());
  std::memcpy(bytes.data() + 2, user_id.data(), std::min<std::size_t>(16, user_id.size()));
  storeLE(bytes.data() + 18, record_id);
  storeLE(bytes.data() + 20, std::uint16_t(payload.size()));
  std::memcpy(bytes.data() + 22, description.data(), std::min<std::size_t>(32, description.size()));
  if (!payload.empty()) std::memcpy(bytes.data() + 54, payload.data(), payload.size());
  return bytes;
}

// What a node's records add to the header and the info VLR.
struct RecordStats {
  LasPointTotals las;
  double gps_min = std::numeric_limits<double>::infinity();
  double gps_max = -std::numeric_limits<double>::infinity();

  // Formats 6-10: x y z at 0, 4, 8; return number in the low 4 bits of byte 14; GPS time at 22.
  void add(const std::byte* records, std::size_t n, std::size_t stride) {
    for (std::size_t i = 0; i < n; ++i) {
      const std::byte* r = records + i * stride;
      const Int3 p{loadLE<std::int32_t>(r), loadLE<std::int32_t>(r + 4),
                   loadLE<std::int32_t>(r + 8)};
      las.addPosition(p);
      const double t = loadLE<double>(r + 22);
      gps_min = std::min(gps_min, t);
      gps_max = std::max(gps_max, t);
      ++las.by_return[std::size_t(std::to_integer<unsigned>(r[14]) & 15u)];
    }
  }
  void merge(const RecordStats& o) {
    las.merge(o.las);
    gps_min = std::min(gps_min, o.gps_min);
    gps_max = std::max(gps_max, o.gps_max);
  }
};

// One node's chunk, between its encoding (any thread) and its writing (in order).
struct EncodedNode {
  std::vector<std::uint8_t> chunk;
  std::uint32_t points = 0;
  RecordStats stats;
};

// The hierarchy pages: which node heads each page, which nodes each page lists, and which of
// them are child pages' heads (-1 entries).
struct PagePlan {
  struct Page {
    std::int32_t head = 0;
    std::vector<std::int32_t> data;     // nodes listed with their chunk (the head first)
    std::vector<std::size_t> children;  // indices of child pages listed by their head
    std::uint64_t offset = 0;
    std::uint64_t size() const { return kCopcEntrySize * (data.size() + children.size()); }
  };
  std::vector<Page> pages;  // the root's first, then breadth first
};

PagePlan planPages(std::span<const OctreeNode> nodes, int page_levels) {
  PagePlan plan;
  plan.pages.push_back({.head = 0});
  for (std::size_t p = 0; p < plan.pages.size(); ++p) {
    const std::int32_t head = plan.pages[p].head;
    const int base = nodes[std::size_t(head)].level;
    std::vector<std::int32_t> level{head};
    plan.pages[p].data.push_back(head);
    while (!level.empty()) {
      std::vector<std::int32_t> next;
      for (const std::int32_t n : level) {
        for (const std::int32_t c : nodes[std::size_t(n)].children) {
          if (c < 0) continue;
          const OctreeNode& child = nodes[std::size_t(c)];
          if (child.level - base >= page_levels && child.child_mask != 0) {
            plan.pages[p].children.push_back(plan.pages.size());
            plan.pages.push_back({.head = c});
          } else {
            plan.pages[p].data.push_back(c);
            next.push_back(c);
          }
        }
      }
      level = std::move(next);
    }
  }
  return plan;
}

CopcKey keyOf(const OctreeNode& node) {
  const std::optional<CopcKey> key = copcKeyOfName(node.name);
  if (!key) {
    throw std::invalid_argument("COPC writer: node name '" + node.name +
                                "' is not an octree path of at most 30 levels");
  }
  return *key;
}

}  // namespace

std::optional<std::string> copcLayoutProblem(const OctreeInfo& info) {
  const double edge = info.cube.max[0] - info.cube.min[0];
  if (!(edge > 0.0) || !std::isfinite(edge)) return "the root box has no extent";
  for (std::size_t axis = 1; axis < 3; ++axis) {
    const double other = info.cube.max[axis] - info.cube.min[axis];
    if (std::abs(other - edge) > 1e-9 * edge) {
      return "the root box is not a cube (COPC's is center +- halfsize)";
    }
  }
  if (!(info.spacing > 0.0) || !std::isfinite(info.spacing)) return "the octree has no spacing";
  return std::nullopt;
}

CopcWriteResult writeCopc(Octree& octree, const std::filesystem::path& path,
                          const CopcWriteOptions& options) {
  if (const auto problem = copcLayoutProblem(octree.info())) {
    throw std::invalid_argument("COPC writer: " + *problem);
  }
  expandWholeOctree(octree);
  const auto nodes = octree.nodes();
  const std::vector<std::int32_t> order = nodesByLevel(octree);
  for (const OctreeNode& node : nodes) {
    keyOf(node);
    if (node.point_count > std::uint32_t(std::numeric_limits<std::int32_t>::max())) {
      throw std::invalid_argument("COPC writer: node " + node.name + " holds over 2^31 points");
    }
  }

  // The record layout, from the first node with points (every node has the same columns).
  LasWriteOptions las;
  las.minor_version = 4;
  PointCloud prototype;
  for (const std::int32_t n : order) {
    if (nodes[std::size_t(n)].point_count > 0) {
      prototype = octree.loadNode(nodes[std::size_t(n)]);
      break;
    }
  }
  prototype.quantization = octree.info().quantization;
  const LasWritePlan plan = planLasWrite(prototype, las);
  const std::optional<LasVlr> extra_bytes = lasExtraBytesVlr(prototype, las);
  laz::LaszipVlr laszip = makeLaszipVlr(plan.point_format, plan.record_length, 1);
  laszip.chunk_size = laz::kVariableChunkSize;

  std::vector<std::vector<std::byte>> vlrs;
  const std::array<std::byte, kCopcInfoSize> no_info{};
  vlrs.push_back(vlrBytes(kCopcUserId, kCopcInfoRecordId, "COPC info VLR", no_info));
  vlrs.push_back(vlrBytes(laz::kLaszipUserId, laz::kLaszipRecordId, "by Parallax",
                          laz::laszipVlrPayload(laszip)));
  for (const LasVlr& vlr : options.vlrs) {
    const bool geotiff = vlr.user_id == "LASF_Projection" && vlr.record_id != 2112;
    const bool ours = vlr.user_id == "LASF_Spec" && vlr.record_id == 4;
    if (geotiff || ours || vlr.user_id == kCopcUserId || vlr.user_id == laz::kLaszipUserId) {
      continue;
    }
    vlrs.push_back(vlrBytes(vlr.user_id, vlr.record_id, vlr.description, vlr.data));
  }
  if (extra_bytes) {
    vlrs.push_back(vlrBytes(extra_bytes->user_id, extra_bytes->record_id, extra_bytes->description,
                            extra_bytes->data));
  }
  std::uint64_t point_data_offset = kLasHeaderSize14;
  for (const auto& vlr : vlrs) point_data_offset += vlr.size();

  OutputFile out(path);
  const std::vector<std::byte> placeholder(kLasHeaderSize14);
  out.write(placeholder.data(), placeholder.size());  // rewritten at the end
  for (const auto& vlr : vlrs) out.write(vlr.data(), vlr.size());
  const std::int64_t table_placeholder = -1;
  out.write(&table_placeholder, 8);

  // The chunks, a batch of nodes at a time.
  tbb::enumerable_thread_specific<std::unique_ptr<laz::ChunkEncoder>> encoders(
      [&] { return laz::makeLayeredEncoder(laszip.items); });
  tbb::enumerable_thread_specific<ByteBuffer> record_buffers;
  std::vector<laz::LazChunk> chunks;
  std::vector<std::uint64_t> node_offset(nodes.size(), 0), node_bytes(nodes.size(), 0);
  std::uint64_t at = point_data_offset + 8;
  RecordStats total;
  CopcWriteResult result;
  forEachNodeInBatches<EncodedNode>(
      octree, order, std::max<std::uint64_t>(1, options.batch_points),
      [&](std::int32_t n, EncodedNode& slot) {
        const OctreeNode& node = nodes[std::size_t(n)];
        slot.chunk.clear();
        slot.points = 0;
        slot.stats = {};
        if (node.point_count == 0) return;
        const PointCloud cloud = octree.loadNode(node);
        ByteBuffer& records = record_buffers.local();
        const std::size_t bytes = std::size_t(cloud.count) * plan.record_length;
        if (records.size() < bytes) records = ByteBuffer(bytes);
        const LasWritePlan node_plan = encodeLasRecords(cloud, las, records.data());
        if (node_plan.record_length != plan.record_length ||
            node_plan.point_format != plan.point_format) {
          throw std::logic_error("COPC writer: node " + node.name +
                                 " has other columns than the first node");
        }
        slot.points = std::uint32_t(cloud.count);
        slot.stats.add(records.data(), slot.points, plan.record_length);
        encoders.local()->encode(records.data(), slot.points, slot.chunk);
      },
      [&](std::int32_t n, EncodedNode& slot) {
        throwIfBuildCancelled(options.cancel);
        if (slot.points == 0) return;
        out.write(slot.chunk.data(), slot.chunk.size());
        chunks.push_back({.offset = at,
                          .bytes = slot.chunk.size(),
                          .first_point = result.points,
                          .points = slot.points});
        node_offset[std::size_t(n)] = at;
        node_bytes[std::size_t(n)] = slot.chunk.size();
        if (slot.chunk.size() > std::uint64_t(std::numeric_limits<std::int32_t>::max())) {
          throw std::invalid_argument("COPC writer: the chunk of node " +
                                      nodes[std::size_t(n)].name + " is over 2 GB");
        }
        at += slot.chunk.size();
        result.points += slot.points;
        total.merge(slot.stats);
        if (options.progress) options.progress->advance(slot.points);
      });

  // The LAZ chunk table.
  const std::uint64_t table_offset = at;
  std::array<std::byte, 8> table_head{};
  storeLE(table_head.data() + 4, std::uint32_t(chunks.size()));
  out.write(table_head.data(), table_head.size());
  const std::vector<std::uint8_t> table = laz::encodeChunkTable(chunks, true);
  out.write(table.data(), table.size());
  at += table_head.size() + table.size();

  // The hierarchy EVLR.
  const PagePlan pages = [&] {
    PagePlan p = planPages(nodes, std::max(1, options.page_levels));
    std::uint64_t offset = at + kLasEvlrHeaderSize;
    for (auto& page : p.pages) {
      page.offset = offset;
      offset += page.size();
    }
    return p;
  }();
  std::vector<std::byte> hierarchy;
  for (const auto& page : pages.pages) {
    for (const std::int32_t n : page.data) {
      const OctreeNode& node = nodes[std::size_t(n)];
      appendCopcEntry({.key = keyOf(node),
                       .offset = node_offset[std::size_t(n)],
                       .byte_size = std::int32_t(node_bytes[std::size_t(n)]),
                       .point_count = std::int32_t(node.point_count)},
                      hierarchy);
    }
    for (const std::size_t c : page.children) {
      const auto& child = pages.pages[c];
      appendCopcEntry({.key = keyOf(nodes[std::size_t(child.head)]),
                       .offset = child.offset,
                       .byte_size = std::int32_t(child.size()),
                       .point_count = -1},
                      hierarchy);
    }
  }
  std::vector<std::byte> evlr(kLasEvlrHeaderSize);
  std::memcpy(evlr.data() + 2, kCopcUserId, 4);
  storeLE(evlr.data() + 18, kCopcHierarchyRecordId);
  storeLE(evlr.data() + 20, std::uint64_t(hierarchy.size()));
  const char description[] = "EPT hierarchy";
  std::memcpy(evlr.data() + 28, description, sizeof description - 1);
  const std::uint64_t evlr_offset = at;
  out.write(evlr.data(), evlr.size());
  out.write(hierarchy.data(), hierarchy.size());
  at += evlr.size() + hierarchy.size();

  // The info VLR, now that the pages and GPS times are known.
  const OctreeInfo& info = octree.info();
  CopcInfo copc;
  const double halfsize = (info.cube.max[0] - info.cube.min[0]) / 2;
  for (std::size_t axis = 0; axis < 3; ++axis) {
    copc.center[axis] = info.cube.min[axis] + halfsize;
  }
  copc.halfsize = halfsize;
  copc.spacing = info.spacing;
  copc.root_hierarchy_offset = pages.pages[0].offset;
  copc.root_hierarchy_size = pages.pages[0].size();
  copc.gps_time_min = result.points > 0 ? total.gps_min : 0.0;
  copc.gps_time_max = result.points > 0 ? total.gps_max : 0.0;
  const auto info_bytes = encodeCopcInfo(copc);
  out.writeAt(kCopcInfoPayloadOffset, info_bytes.data(), info_bytes.size());
  std::array<std::byte, 8> table_at;
  storeLE(table_at.data(), std::int64_t(table_offset));
  out.writeAt(point_data_offset, table_at.data(), table_at.size());

  // The LAS 1.4 header.
  LasHeader fields;
  fields.version_minor = 4;
  fields.global_encoding = std::uint16_t((options.gps_time_standard.value_or(false) ? 1 : 0) | 16);
  stampGeneratedBy(fields);
  fields.point_data_offset = std::uint32_t(point_data_offset);
  fields.vlr_count = std::uint32_t(vlrs.size());
  fields.point_format = plan.point_format;
  fields.record_length = std::uint16_t(plan.record_length);
  fields.quantization = info.quantization;
  total.las.writeTo(fields, result.points);
  fields.evlr_offset = evlr_offset;
  fields.evlr_count = 1;                                                // the hierarchy
  const std::vector<std::byte> header = encodeLasHeader(fields, true);  // LASzip-compressed
  out.writeAt(0, header.data(), header.size());
  out.commit();

  result.nodes = nodes.size();
  result.chunks = chunks.size();
  result.pages = pages.pages.size();
  result.point_format = plan.point_format;
  result.bytes = at;
  return result;
}

}  // namespace parallax
