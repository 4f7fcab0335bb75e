// Options of the level-of-detail octree build, shared by the in-memory path (in_memory_octree.h)
// and the out-of-core conversion to Potree 2.0 (potree_converter.h), and the geometry both use:
// the root cube, node boxes and node spacing.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>

#include "core/bounds.h"
#include "core/progress.h"

namespace parallax {

enum class SamplingMethod {
  // Poisson-disk: an inner node keeps a point only when no point it already kept lies closer
  // than the node's spacing (Potree's default). Even density, the better picture.
  Poisson,
  // One point per grid cell of the node's spacing, no distance test: faster, less even.
  Random,
};

// "poisson" / "random"; parseSamplingMethod accepts the same names (false for anything else).
const char* samplingMethodName(SamplingMethod method);
bool parseSamplingMethod(std::string_view name, SamplingMethod& method);

struct OctreeBuildOptions {
  SamplingMethod sampling = SamplingMethod::Poisson;
  // Root spacing in world units; 0 picks the root cube's edge / 128 (as PotreeConverter does,
  // so a root holds roughly 128 x 128 points of a surface). Node spacing halves per level.
  double spacing = 0.0;
  // A node holding more points than this after sampling its subtree is split.
  std::uint32_t max_node_points = 20'000;
  // Out of core: the memory the conversion may use, in bytes (--memory MB). It sizes the chunks
  // and the spill buffers; see potree_converter.h for what counts.
  std::uint64_t memory_bytes = 2048ull << 20;
  // Out of core: overrides the chunk size derived from memory_bytes (tests force many chunks).
  std::uint64_t max_chunk_points = 0;
  // Worker threads; 0 uses every core.
  int threads = 0;
  // Out of core: keep the decoded points of every input for the passes after the scan, not only
  // of those that do not reread cheaply (io/point_format.h). For `bench convert --keep-all`,
  // which measures what rereading costs (lod/NOTES.md "Each point decoded once").
  bool keep_all_decoded = false;
  Progress* progress = nullptr;  // advanced by points (each stage reports its own share)
  // Set by another thread to stop the conversion: checked once a batch of the scan, count and
  // distribute passes, once a chunk of the build and once a node of the COPC write (never per
  // point); the conversion then throws OctreeBuildCancelled and leaves no output and no work
  // files (the temporary directory is removed as on any error). Null: not cancellable.
  const std::atomic<bool>* cancel = nullptr;
};

// What a conversion whose OctreeBuildOptions::cancel was set throws.
struct OctreeBuildCancelled : std::runtime_error {
  OctreeBuildCancelled() : std::runtime_error("octree build: cancelled") {}
};

// Throws OctreeBuildCancelled when `cancel` is set; null never is.
inline void throwIfBuildCancelled(const std::atomic<bool>* cancel) {
  if (cancel && cancel->load(std::memory_order_relaxed)) throw OctreeBuildCancelled();
}

// The root cube of a cloud: its bounds' minimum corner and the largest extent as edge (a point
// on the maximum face still falls inside: octant tests clamp). Never zero-sized: a single point
// gets an edge of 1.
Bounds3 octreeCube(const Bounds3& bounds);

// options.spacing, or cube edge / 128 when it is 0.
double rootSpacing(const Bounds3& cube, const OctreeBuildOptions& options);

// Child `index` of a node box (bit 4 = +x, bit 2 = +y, bit 1 = +z; Potree's numbering).
Bounds3 childBox(const Bounds3& box, int index);

// The box of the node named `name` ("r", "r0", "r07", ...) inside `cube`.
Bounds3 nodeBox(const Bounds3& cube, std::string_view name);

}  // namespace parallax
