#include "measure/height_profile.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>
#include <numeric>
#include <optional>

#include "core/error.h"
#include "core/point_gather.h"
#include "io/las_writer.h"

namespace parallax {

namespace {

// The polyline in the XY plane, with each segment's start station, ready to test points.
class Corridor {
 public:
  Corridor(const std::vector<glm::dvec3>& line, double width) : half_width_(0.5 * width) {
    double station = 0;
    for (std::size_t i = 1; i < line.size(); ++i) {
      const glm::dvec2 a(line[i - 1]), b(line[i]);
      const double length = glm::length(b - a);
      // A vertical segment (same XY twice) has no direction on the ground: it adds no station and
      // no corridor of its own (its neighbours' cover the spot).
      if (length > 0) {
        segments_.push_back({a, b - a, (b - a) / length, glm::dot(b - a, b - a), length, station});
      }
      station += length;
    }
    for (const glm::dvec3& p : line) {
      lo_ = glm::min(lo_, glm::dvec2(p) - half_width_);
      hi_ = glm::max(hi_, glm::dvec2(p) + half_width_);
    }
  }

  bool empty() const { return segments_.empty() || !(half_width_ > 0); }
  // The XY box of the corridor (every vertex grown by the half width).
  glm::dvec2 lo() const { return lo_; }
  glm::dvec2 hi() const { return hi_; }

  // The point's station and signed offset on the nearest segment whose corridor holds it.
  std::optional<std::pair<double, double>> place(const glm::dvec2& p) const {
    std::optional<std::pair<double, double>> best;
    double best_distance = std::numeric_limits<double>::infinity();
    for (const Segment& s : segments_) {
      const glm::dvec2 d = p - s.start;
      // The foot's place against the segment unnormalised: the end vertex itself (d == delta)
      // is then exactly at the end and inside, which (d . direction) <= length, one rounding
      // off, may not be.
      const double scaled = glm::dot(d, s.delta);
      if (scaled < 0 || scaled > s.length2) continue;
      const double along = std::min(scaled / s.length, s.length);
      // Left of the direction of travel is positive (the z of direction x d).
      const double offset = s.direction.x * d.y - s.direction.y * d.x;
      if (std::abs(offset) <= half_width_ && std::abs(offset) < best_distance) {
        best_distance = std::abs(offset);
        best = std::pair{s.station + along, offset};
      }
    }
    return best;
  }

 private:
  struct Segment {
    glm::dvec2 start, delta, direction;  // delta: end - start; direction: delta / length
    double length2, length, station;
  };
  std::vector<Segment> segments_;
  double half_width_;
  glm::dvec2 lo_{std::numeric_limits<double>::infinity()};
  glm::dvec2 hi_{-std::numeric_limits<double>::infinity()};
};

struct Found {
  std::vector<ProfileSample> samples;
  std::vector<std::uint64_t> indices;  // into the cloud searched
};

Found search(const PointCloud& cloud, const Corridor& corridor) {
  Found found;
  for (std::uint64_t i = 0; i < cloud.count; ++i) {
    const glm::dvec3 p(cloud.worldX(i), cloud.worldY(i), cloud.worldZ(i));
    if (p.x < corridor.lo().x || p.x > corridor.hi().x || p.y < corridor.lo().y ||
        p.y > corridor.hi().y) {
      continue;
    }
    if (auto placed = corridor.place(glm::dvec2(p))) {
      found.samples.push_back({placed->first, placed->second, p});
      found.indices.push_back(i);
    }
  }
  return found;
}

// The samples ordered by station (then by the source's order), the points with them.
HeightProfile ordered(const PointCloud& cloud, Found found) {
  std::vector<std::uint64_t> order(found.samples.size());
  std::iota(order.begin(), order.end(), std::uint64_t{0});
  std::stable_sort(order.begin(), order.end(), [&](std::uint64_t a, std::uint64_t b) {
    return found.samples[a].station < found.samples[b].station;
  });
  HeightProfile profile;
  std::vector<std::uint64_t> indices(order.size());
  for (std::size_t i = 0; i < order.size(); ++i) {
    profile.samples.push_back(found.samples[order[i]]);
    indices[i] = found.indices[order[i]];
  }
  profile.points = gatherPoints(cloud, indices);
  profile.points.quantization = cloud.quantization;
  profile.points.source = cloud.source;
  profile.points.computeBounds();
  return profile;
}

template <class T>
void appendColumn(Column<T>& into, std::uint64_t at, const Column<T>& from) {
  if (!from.empty()) std::memcpy(into.data() + at, from.data(), from.size() * sizeof(T));
}

// The clouds one after the other. They come from one octree: the same columns, scalars and
// quantization.
PointCloud concatenate(std::vector<PointCloud>& parts, const PointCloud& shape) {
  std::uint64_t total = 0;
  for (const PointCloud& part : parts) total += part.count;
  PointCloud all;
  all.count = total;
  all.quantization = shape.quantization;
  all.source = shape.source;
  all.positions = Column<Int3>(total);
  if (shape.hasColors()) all.colors = Column<Rgba8>(total);
  if (shape.hasNormals()) all.normals = Column<Float3>(total);
  if (shape.hasIntensity()) all.intensity = Column<float>(total);
  if (shape.hasClassification()) all.classification = Column<std::uint8_t>(total);
  for (const ScalarColumn& scalar : shape.scalars) {
    all.scalars.push_back({scalar.name, scalar.type, ByteBuffer(total * scalarSize(scalar.type))});
  }
  std::uint64_t at = 0;
  for (const PointCloud& part : parts) {
    appendColumn(all.positions, at, part.positions);
    if (all.hasColors()) appendColumn(all.colors, at, part.colors);
    if (all.hasNormals()) appendColumn(all.normals, at, part.normals);
    if (all.hasIntensity()) appendColumn(all.intensity, at, part.intensity);
    if (all.hasClassification()) appendColumn(all.classification, at, part.classification);
    for (std::size_t s = 0; s < all.scalars.size() && s < part.scalars.size(); ++s) {
      const std::size_t size = scalarSize(all.scalars[s].type);
      if (part.scalars[s].data.size() == part.count * size) {
        std::memcpy(all.scalars[s].data.data() + at * size, part.scalars[s].data.data(),
                    part.count * size);
      }
    }
    at += part.count;
  }
  return all;
}

bool boxMeetsCorridor(const Bounds3& box, const Corridor& corridor) {
  return box.max[0] >= corridor.lo().x && box.min[0] <= corridor.hi().x &&
         box.max[1] >= corridor.lo().y && box.min[1] <= corridor.hi().y;
}

std::string fullPrecision(double value) {
  char text[64];
  std::snprintf(text, sizeof text, "%.17g", value);
  return text;
}

}  // namespace

HeightProfile extractProfile(const PointCloud& cloud, const std::vector<glm::dvec3>& line,
                             double width) {
  const Corridor corridor(line, width);
  if (corridor.empty()) return ordered(cloud, {});
  return ordered(cloud, search(cloud, corridor));
}

HeightProfile extractProfile(Octree& octree, const std::vector<glm::dvec3>& line, double width,
                             std::uint64_t max_points) {
  const Corridor corridor(line, width);
  std::vector<PointCloud> parts;
  Found all;
  std::optional<PointCloud> shape;
  if (!corridor.empty() && !octree.nodes().empty()) {
    std::vector<std::int32_t> stack{0};
    while (!stack.empty()) {
      const std::int32_t index = stack.back();
      stack.pop_back();
      if (!boxMeetsCorridor(octree.nodes()[std::size_t(index)].box, corridor)) continue;
      if (octree.nodes()[std::size_t(index)].hierarchy_pending) octree.expandHierarchy(index);
      const OctreeNode node = octree.nodes()[std::size_t(index)];  // (expanding may reallocate)
      for (std::int32_t child : node.children) {
        if (child >= 0) stack.push_back(child);
      }
      if (node.point_count == 0) continue;
      PointCloud points = octree.loadNodeWhole(node);
      Found found = search(points, corridor);
      if (found.samples.empty()) continue;
      if (all.samples.size() + found.samples.size() > max_points) {
        throw InputError({.file = "the height profile",
                          .expected = "at most " + std::to_string(max_points) + " points",
                          .found = "more in its corridor",
                          .hint = "narrow the corridor or shorten the line"});
      }
      // Indices into the concatenation of the parts.
      std::uint64_t base = 0;
      for (const PointCloud& part : parts) base += part.count;
      for (std::size_t i = 0; i < found.samples.size(); ++i) {
        all.samples.push_back(found.samples[i]);
        all.indices.push_back(base + i);
      }
      parts.push_back(gatherPoints(points, found.indices));
      if (!shape) shape = std::move(points);
    }
  }
  if (!shape) {
    PointCloud empty;
    empty.quantization = octree.info().quantization;
    return ordered(empty, {});
  }
  const PointCloud joined = concatenate(parts, *shape);
  return ordered(joined, std::move(all));
}

HeightRange heightRange(const HeightProfile& profile) {
  if (profile.samples.empty()) return {};
  HeightRange range{profile.samples.front().position.z, profile.samples.front().position.z};
  for (const ProfileSample& sample : profile.samples) {
    range.low = std::min(range.low, sample.position.z);
    range.high = std::max(range.high, sample.position.z);
  }
  return range;
}

void writeProfileCsv(const HeightProfile& profile, const std::filesystem::path& path) {
  const std::filesystem::path partial = path.string() + ".partial";
  {
    std::ofstream out(partial, std::ios::binary | std::ios::trunc);
    if (!out) throw std::runtime_error("cannot write the profile CSV " + partial.string());
    out << "station,height,offset,x,y,z\n";
    for (const ProfileSample& s : profile.samples) {
      out << fullPrecision(s.station) << ',' << fullPrecision(s.position.z) << ','
          << fullPrecision(s.offset) << ',' << fullPrecision(s.position.x) << ','
          << fullPrecision(s.position.y) << ',' << fullPrecision(s.position.z) << '\n';
    }
    out.flush();
    if (!out) {
      std::error_code ignored;
      std::filesystem::remove(partial, ignored);
      throw std::runtime_error("cannot write the profile CSV " + partial.string());
    }
  }
  std::error_code error;
  std::filesystem::rename(partial, path, error);
  if (error) {
    std::error_code ignored;
    std::filesystem::remove(partial, ignored);
    throw std::runtime_error("cannot write the profile CSV " + path.string() + ": " +
                             error.message());
  }
}

void writeProfileLas(const HeightProfile& profile, const std::filesystem::path& path) {
  writeLas(profile.points, path);
}

}  // namespace parallax
