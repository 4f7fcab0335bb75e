#include "lod/copc_format.h"

#include <bit>
#include <cstring>
#include "core/byte_order.h"

namespace parallax {
namespace {

static_assert(std::endian::native == std::endian::little, "COPC records are little endian");

}  // namespace

Bounds3 CopcInfo::cube() const {
  Bounds3 box;
  for (std::size_t axis = 0; axis < 3; ++axis) {
    box.min[axis] = center[axis] - halfsize;
    box.max[axis] = center[axis] + halfsize;
  }
  return box;
}

CopcInfo parseCopcInfo(std::span<const std::byte, kCopcInfoSize> bytes) {
  const std::byte* p = bytes.data();
  CopcInfo info;
  for (std::size_t axis = 0; axis < 3; ++axis) info.center[axis] = loadLE<double>(p + 8 * axis);
  info.halfsize = loadLE<double>(p + 24);
  info.spacing = loadLE<double>(p + 32);
  info.root_hierarchy_offset = loadLE<std::uint64_t>(p + 40);
  info.root_hierarchy_size = loadLE<std::uint64_t>(p + 48);
  info.gps_time_min = loadLE<double>(p + 56);
  info.gps_time_max = loadLE<double>(p + 64);
  return info;
}

std::array<std::byte, kCopcInfoSize> encodeCopcInfo(const CopcInfo& info) {
  std::array<std::byte, kCopcInfoSize> bytes{};  // the 11 reserved words stay zero
  std::byte* p = bytes.data();
  for (std::size_t axis = 0; axis < 3; ++axis) storeLE(p + 8 * axis, info.center[axis]);
  storeLE(p + 24, info.halfsize);
  storeLE(p + 32, info.spacing);
  storeLE(p + 40, info.root_hierarchy_offset);
  storeLE(p + 48, info.root_hierarchy_size);
  storeLE(p + 56, info.gps_time_min);
  storeLE(p + 64, info.gps_time_max);
  return bytes;
}

bool CopcKey::valid() const {
  if (level < 0 || level > kCopcMaxLevel) return false;
  const std::int64_t side = std::int64_t{1} << level;
  auto inside = [side](std::int32_t v) { return v >= 0 && v < side; };
  return inside(x) && inside(y) && inside(z);
}

CopcKey CopcKey::child(int digit) const {
  return {level + 1, 2 * x + ((digit >> 2) & 1), 2 * y + ((digit >> 1) & 1), 2 * z + (digit & 1)};
}

bool CopcKey::within(const CopcKey& ancestor) const {
  if (level < ancestor.level) return false;
  const int shift = level - ancestor.level;
  return (x >> shift) == ancestor.x && (y >> shift) == ancestor.y && (z >> shift) == ancestor.z;
}

std::string CopcKey::text() const {
  std::string out = std::to_string(level);
  for (std::int32_t v : {x, y, z}) {
    out += '-';
    out += std::to_string(v);
  }
  return out;
}

std::string copcNodeName(const CopcKey& key) {
  std::string name = "r";
  for (int l = key.level - 1; l >= 0; --l) {
    const int digit = (((key.x >> l) & 1) << 2) | (((key.y >> l) & 1) << 1) | ((key.z >> l) & 1);
    name += char('0' + digit);
  }
  return name;
}

std::optional<CopcKey> copcKeyOfName(const std::string& name) {
  if (name.empty() || name[0] != 'r' || name.size() > std::size_t(kCopcMaxLevel) + 1) {
    return std::nullopt;
  }
  CopcKey key;
  for (std::size_t i = 1; i < name.size(); ++i) {
    if (name[i] < '0' || name[i] > '7') return std::nullopt;
    key = key.child(name[i] - '0');
  }
  return key;
}

Bounds3 copcNodeBox(const Bounds3& root, const CopcKey& key) {
  Bounds3 box;
  const double cells = double(std::int64_t{1} << key.level);
  const std::int32_t index[3] = {key.x, key.y, key.z};
  for (std::size_t axis = 0; axis < 3; ++axis) {
    const double size = (root.max[axis] - root.min[axis]) / cells;
    box.min[axis] = root.min[axis] + size * index[axis];
    // The last cube ends exactly on the root's face (no rounding gap at the border).
    box.max[axis] = index[axis] + 1 == std::int64_t(cells)
                        ? root.max[axis]
                        : root.min[axis] + size * (index[axis] + 1);
  }
  return box;
}

std::vector<CopcEntry> parseCopcPage(std::span<const std::byte> bytes) {
  std::vector<CopcEntry> entries(bytes.size() / kCopcEntrySize);
  for (std::size_t i = 0; i < entries.size(); ++i) {
    const std::byte* p = bytes.data() + i * kCopcEntrySize;
    CopcEntry& e = entries[i];
    e.key = {loadLE<std::int32_t>(p), loadLE<std::int32_t>(p + 4), loadLE<std::int32_t>(p + 8),
             loadLE<std::int32_t>(p + 12)};
    e.offset = loadLE<std::uint64_t>(p + 16);
    e.byte_size = loadLE<std::int32_t>(p + 24);
    e.point_count = loadLE<std::int32_t>(p + 28);
  }
  return entries;
}

void appendCopcEntry(const CopcEntry& entry, std::vector<std::byte>& out) {
  const std::size_t at = out.size();
  out.resize(at + kCopcEntrySize);
  std::byte* p = out.data() + at;
  storeLE(p, entry.key.level);
  storeLE(p + 4, entry.key.x);
  storeLE(p + 8, entry.key.y);
  storeLE(p + 12, entry.key.z);
  storeLE(p + 16, entry.offset);
  storeLE(p + 24, entry.byte_size);
  storeLE(p + 28, entry.point_count);
}

}  // namespace parallax
