#include "render_scene.h"

#include <algorithm>
#include <cstdio>
#include <optional>
#include <stdexcept>

#include "core/byte_source_opener.h"
#include "core/error.h"
#include "core/url.h"
#include "io/ply_preview.h"
#include "io/point_file.h"
#include "lod/drawing_input.h"
#include "lod/octree_open.h"
#include "lod/potree_reader.h"
#include "progress_options.h"

namespace parallax::cli {

RenderSource openRenderSource(const RenderSourceOptions& o, const LodOptions& lod) {
  const std::string command(o.command);
  RenderSource source;
  const DrawingInput drawing = planDrawing(o.input, lod.budget);
  if (drawing.kind == DrawingKind::Octree) {  // a Potree directory or a COPC file
    source.octree_dir = o.input;
    source.octree = openOctree(o.input);
    source.octree->selectAttributes(o.attributes);
    return source;
  }
  if (drawing.kind == DrawingKind::WholeFile) {
    const auto progress = readingBar(o.quiet, "loading", o.input);
    source.cloud = readPointFile(
        o.input, {.progress = progress.get(), .attributes = o.attributes});  // every point drawn
    return source;
  }
  if (o.preview) {
    std::optional<PointCloud> preview = readDrawingPreview(o.input, lod.budget);
    if (!preview) {
      throw std::invalid_argument(
          "--preview: " + o.input + " is a " + pointFormatName(detectPointFormat(o.input)) +
          " file (samples are read from " + previewFormatNamesText() + " files)");
    }
    source.cloud = std::move(*preview);
    source.file_points = drawing.points;
    return source;
  }
  if (isUrl(o.input)) {
    // The octree cache keys a file by its path and time on this disk; a URL has neither, and
    // building its octree here would fetch the whole file anyway.
    throw InputError({.file = urlForMessages(o.input),
                      .expected = "a point file within the point budget (" +
                                  std::to_string(lod.budget) + " points) when drawn from a URL",
                      .found = std::to_string(drawing.points) + " points",
                      .hint = "--preview draws a sample read by range; or raise --budget; or "
                              "convert it to an octree first (parallax convert URL -o DIR/) and "
                              "serve that"});
  }
  const OctreeCacheSettings cache = octreeCacheSettingsFrom(lod);
  source.location = std::make_unique<OctreeLocation>(o.input, cache);
  const std::string directory = source.location->directory().string();
  if (source.location->complete()) {
    if (!o.quiet)
      std::fprintf(stderr,
                   "parallax %s: %llu points, over the budget of %llu: using the octree in %s\n",
                   command.c_str(), static_cast<unsigned long long>(drawing.points),
                   static_cast<unsigned long long>(lod.budget), directory.c_str());
  } else {
    if (!o.quiet)
      std::fprintf(stderr,
                   "parallax %s: %llu points, over the budget of %llu: converting to an octree "
                   "in %s\n",
                   command.c_str(), static_cast<unsigned long long>(drawing.points),
                   static_cast<unsigned long long>(lod.budget), directory.c_str());
    ensureOctree(*source.location, cache.build, stageBars(o.quiet));
  }
  source.octree_dir = source.location->directory();
  source.octree = openPotree(source.octree_dir);
  return source;
}

std::optional<ScalarRange> paintScalarColors(RenderSource& source, const RenderOptions& options,
                                             bool quiet, std::string_view command) {
  const ScalarColoring coloring = renderSettingsFrom(options, 0.0).scalar;
  if (coloring.field.empty()) return std::nullopt;
  if (source.lod()) {
    throw std::invalid_argument("--color " + coloring.field +
                                ": scalar attributes are coloured on whole clouds, and " +
                                source.octree_dir.string() +
                                " is drawn as an octree (raise --budget over its point count, or "
                                "use --preview)");
  }
  const ScalarRange range = paintScalarField(source.cloud, coloring);
  if (!quiet)
    std::fprintf(stderr, "parallax %s: %s from %.9g to %.9g, %s ramp\n",
                 std::string(command).c_str(), coloring.field.c_str(), range.min, range.max,
                 std::string(colorRampName(coloring.ramp)).c_str());
  return range;
}

RenderScene uploadRenderSource(RenderSource& source, bool keep_cloud) {
  RenderScene scene;
  if (source.lod()) {
    scene.lod = std::make_unique<LodScene>(*source.octree);
    scene.extent = viewExtentOf(*source.octree);
    scene.points = source.octree->info().point_count;
  } else {
    scene.gpu = std::make_unique<GpuPointCloud>(source.cloud);
    scene.whole = scene.gpu->drawSet();
    glFinish();
    scene.extent = viewExtentOf(source.cloud);
    scene.points = source.cloud.count;
    if (!keep_cloud) source.cloud = PointCloud();  // the GPU holds the points now
  }
  return scene;
}

StereoSettings headlessStereoSettings(const RenderOptions& options, bool quiet,
                                      std::string_view command) {
  StereoSettings stereo = stereoSettingsFrom(options);
  if (stereo.mode == StereoMode::QuadBuffer) {
    if (!quiet)
      std::fprintf(stderr,
                   "parallax %s: quad-buffer stereo needs a window with a stereo (GL_STEREO) "
                   "visual, and a headless render has none: falling back to sbs (side by side)\n",
                   std::string(command).c_str());
    stereo.mode = StereoMode::SideBySide;
  }
  return stereo;
}

namespace {

// A node that failed to load is an error of the input for the commands that draw an octree.
void throwOnFailedNodes(const RenderScene& scene, const RenderSource& source) {
  if (scene.lod->firstError().empty()) return;
  throw InputError({.file = urlForMessages(source.octree_dir.string()),
                    .expected = "every node the view selects readable",
                    .found = std::to_string(scene.lod->stats().failed_nodes) +
                             " failed, the first: " + scene.lod->firstError()});
}

}  // namespace

const DrawSet& frameDrawSet(RenderScene& scene, const RenderSource& source,
                            const StereoFrame& frame, const LodOptions& lod) {
  if (!scene.lod) return scene.whole;
  const DrawSet& draw_set = scene.lod->finishLoading(frame.views, lodFrameSettingsFrom(lod));
  throwOnFailedNodes(scene, source);
  return draw_set;
}

const DrawSet& arrivedDrawSet(RenderScene& scene, const RenderSource& source,
                              const StereoFrame& frame, const LodOptions& lod) {
  if (!scene.lod) return scene.whole;
  const DrawSet& draw_set = scene.lod->update(frame.views, lodFrameSettingsFrom(lod));
  throwOnFailedNodes(scene, source);
  return draw_set;
}

}  // namespace parallax::cli
