// What `parallax render` and `parallax pick` share: opening INPUT as a whole cloud, a preview
// sample or an octree (converting a file over --budget first), putting it on the GPU, and the draw
// set of one frame. One place, so that `pick` answers for exactly the picture `render` writes.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include "core/point_cloud.h"
#include "lod/octree.h"
#include "lod/octree_cache.h"
#include "render/draw_set.h"
#include "render/lod_scene.h"
#include "render/point_buffers.h"
#include "render/stereo.h"
#include "render/view_extent.h"
#include "render_options.h"

namespace parallax::cli {

// What the frames draw: a whole cloud uploaded at once (a file within the budget, or --preview's
// sample of a larger one), or an octree streamed through a LodScene (a Potree directory, a COPC
// file, or the octree of a file over the budget).
struct RenderSource {
  PointCloud cloud;                          // until uploaded (kept with keep_cloud)
  std::uint64_t file_points = 0;             // --preview: the file's point count
  std::unique_ptr<OctreeLocation> location;  // keeps a --no-cache octree until the end
  std::filesystem::path octree_dir;
  std::unique_ptr<Octree> octree;
  bool lod() const { return octree != nullptr; }
};

struct RenderSourceOptions {
  std::string input;
  bool preview = false;
  bool quiet = false;
  std::string_view command = "render";  // names the command in messages on stderr
  // What the picture needs (attributesDrawn): a LAZ file within the budget and a COPC file read
  // only those. Every attribute by default (pick reports a point's every attribute).
  AttributeSelection attributes;
};

// Opens the input; throws InputError or std::invalid_argument naming the file or option.
RenderSource openRenderSource(const RenderSourceOptions& options, const LodOptions& lod);

// With `--color ATTRIBUTE` (a scalar attribute, not a colour mode), replaces the whole cloud's
// colours with the attribute's ramp (render/scalar_colors.h) and, unless `quiet`, says the range
// on stderr. Throws std::invalid_argument naming the attribute and those the cloud has, and for an
// octree (its nodes carry no scalar attributes for the renderer). Returns the range used;
// std::nullopt without a scalar attribute.
std::optional<ScalarRange> paintScalarColors(RenderSource& source, const RenderOptions& options,
                                             bool quiet, std::string_view command);

// The source on the GPU (needs a current context): the whole cloud, or a LodScene.
struct RenderScene {
  std::unique_ptr<GpuPointCloud> gpu;
  std::unique_ptr<LodScene> lod;
  DrawSet whole;      // gpu's draw set
  ViewExtent extent;  // what the default camera frames
  std::uint64_t points = 0;
};
// Uploads `source`; its cloud is freed after the upload unless `keep_cloud` (picking reads
// points back from it).
RenderScene uploadRenderSource(RenderSource& source, bool keep_cloud);

// The stereo settings of the options; quad-buffer, which needs a window, falls back to sbs (with
// a message unless `quiet`).
StereoSettings headlessStereoSettings(const RenderOptions& options, bool quiet,
                                      std::string_view command);

// The finished draw set of a frame: for an octree, it waits for every node the views select, and
// throws InputError where one failed to load.
const DrawSet& frameDrawSet(RenderScene& scene, const RenderSource& source,
                            const StereoFrame& frame, const LodOptions& lod);
// The draw set of a frame that must never wait (a headset's, whose runtime drops a late frame):
// for an octree, what has arrived for the views (LodScene::update: missing nodes are requested
// and drawn in a later frame, their parents meanwhile), as the window's progressive frames are.
// Throws InputError where a node failed to load, as frameDrawSet does.
const DrawSet& arrivedDrawSet(RenderScene& scene, const RenderSource& source,
                              const StereoFrame& frame, const LodOptions& lod);

}  // namespace parallax::cli
