// The compute-shader rasterizer: points drawn with an atomic minimum per pixel instead of
// GL_POINTS (Schuetz, Kerbl, Wimmer, "Rendering Point Clouds with Compute Shaders and Vertex
// Order Optimization", 2021), into the same targets as the GL_POINTS pass.
//
// Work: every chunk is cut into batches of kBatchPoints consecutive (Morton-ordered) points with
// their boxes (PointChunk::batches_offset). One workgroup per batch; a batch that no view sees
// returns before it reads a point. Each point is read once and projected into every view that
// sees its batch (stereo in one pass).
//
// The visibility buffer holds one entry per canvas pixel: a depth key (the reversed window depth's
// bits, inverted so that nearer is smaller) and the id of the front-most point. Ids count the
// points of the draw set in its order, so that the pick of a pixel is one exact point.
//   64-bit path, where the context has GL_NV_shader_atomic_int64 and GL_ARB_gpu_shader_int64:
//     pass 1 does one atomicMin(key << 32 | id) per pixel; pass 2 lets the point whose (key, id)
//     won write its colour (no race, no atomic). Ties: the lowest id, as GL_POINTS (first drawn).
//   32-bit path (llvmpipe, AMD, Intel): pass 1 does atomicMin(key) after a plain read (a point
//     behind the stored key stays behind); pass 2 lets every point at exactly the stored key do
//     atomicMin(id) and atomicMin(packed colour). Ties: the lowest id is picked and the lowest
//     packed colour shown; both are the same every run, whatever the threads' order.
// The paths differ in those few lines of the shader only (compute_rasterizer_glsl.cpp).
// A resolve pass then writes colour, eye depth and depth into the bound framebuffer.
//
// Every colour mode, lighting, the point filter, fixed, attenuated and adaptive sizes are computed
// as the GL_POINTS shader does, and every size GL_POINTS draws is a splat here too (square, or
// round by the same disc test), up to the GL's largest point (GL_POINT_SIZE_RANGE, 255 pixels on
// llvmpipe), so no look is left to GL_POINTS. A splat up to kInlineSplatPx wide is walked by the
// invocation that reads its point; a wider one is listed by the pass and drawn by the LARGE
// program after each group of ranges (its invocations share a splat's pixels), with the same
// depth key, id and colour, so the picture does not depend on which way a splat went. HQ mode blends,
// per pixel, every point within a relative depth range of the front-most one.
//
// Bindings: attributes through buffer textures and the visibility buffer through SSBOs, each
// bound range at most `max_range_bytes` (llvmpipe binds at most 128 MiB to one SSBO).
#pragma once

#include <epoxy/gl.h>

#include <cstdint>
#include <map>
#include <optional>
#include <vector>

#include "render/rasterizer.h"
#include "render/shader_program.h"

namespace parallax {

struct ComputeRasterizerOptions {
  // Largest range of a buffer bound at once (bytes): llvmpipe's SSBO limit. Tests lower it to
  // exercise the ranges.
  std::size_t max_range_bytes = std::size_t(128) << 20;
  // False: the 32-bit path even where 64-bit atomics exist (to compare both on one GPU).
  bool allow_64bit_atomics = true;
  // Large splats listed before they are drawn, at most (32 bytes each; also within one SSBO
  // binding, and at least a batch of points in kMaxViews views). A frame's ranges are grouped so
  // that a group's points in all views fit; tests lower it to exercise several groups.
  std::uint32_t large_splats_per_group = 1u << 20;
  // True: views whose clip depth and w are view 0's (an off-axis pair, a headset's parallel
  // eyes) are projected in depth once for all (see shareDepth). False: each view projected
  // alone (the reference the tests compare the shared path with).
  bool share_depth = true;
  // True: glFinish after the clears and after each pass, and each timed (passTimesOfLastFrame).
  // For benchmarks: the waits cost a little and stop the GPU from overlapping the passes.
  bool time_passes = false;
};

// One frame's passes timed apart (ComputeRasterizerOptions::time_passes): wall and process CPU
// milliseconds (the CPU time is llvmpipe's threads together; on a GPU it is the driver's).
// `clear` holds the clears and the frame's setup (culling, the batches' order).
struct ComputePassTimes {
  double clear_ms = 0, pass1_ms = 0, pass2_ms = 0, resolve_ms = 0;
  double clear_cpu_ms = 0, pass1_cpu_ms = 0, pass2_cpu_ms = 0, resolve_cpu_ms = 0;
};

// A point found in the visibility buffer.
struct PointRef {
  std::size_t item = 0;               // in the draw set that was drawn
  const PointChunk* chunk = nullptr;  // that item's chunk
  std::uint32_t index = 0;            // in the chunk
  std::uint32_t id = 0;               // in the frame: the item's first id + index
  float depth = 0.0f;                 // reversed window depth (as the depth buffer holds it)
};

class ComputeRasterizer final : public Rasterizer {
 public:
  // Widest splat (pixels) the invocation that reads its point draws itself; wider ones are listed
  // and drawn a workgroup each (see NOTES.md, "Large splats", for the measurement).
  static constexpr float kInlineSplatPx = 8.0f;
  // The widest inline splat for a frame of `views` views: kInlineSplatPx, or less where
  // llvmpipe's loop limit would cut an invocation's work short (see the definition).
  static float inlineSplatPx(std::size_t views);
  // Views drawn in one pass (a stereo pair needs two).
  static constexpr std::size_t kMaxViews = 4;

  explicit ComputeRasterizer(const ComputeRasterizerOptions& options = {});  // current 4.5 context
  ~ComputeRasterizer() override;
  ComputeRasterizer(const ComputeRasterizer&) = delete;
  ComputeRasterizer& operator=(const ComputeRasterizer&) = delete;

  RasterizerKind kind() const override { return RasterizerKind::Compute; }
  std::string unsupported(const RenderSettings& settings, int canvas_width,
                          int canvas_height) const override;
  // Clears the visibility buffer (unless frame.accumulate), runs both passes over the frame's
  // items (and the large splats' passes) and resolves into the bound framebuffer.
  RasterStats draw(const RasterFrame& frame) override;

  // The largest point size (pixels) both rasterizers draw: GL_POINT_SIZE_RANGE's maximum.
  float maxPointSize() const { return max_point_px_; }
  // Splats the last frame drew a workgroup each (wider than an inline splat). Reads the count
  // back from the GPU (a sync): for tests, benchmarks and reports, not for every frame.
  std::uint64_t largeSplatsOfLastFrame() const;

  // Whether the last frame's views shared one projection of depth (share_depth, and the views
  // allow it). For tests and benchmarks: a stereo frame that silently lost it costs more.
  bool sharedDepthOfLastFrame() const { return shared_depth_; }

  // The last frame's passes, timed where options.time_passes is set (zeros otherwise).
  const ComputePassTimes& passTimesOfLastFrame() const { return pass_times_; }

  // True where the 64-bit path runs (the context has the extensions and the options allow it).
  bool uses64BitAtomics() const { return atomic64_; }

  // The front-most point at canvas pixel (x, y) of the last frame (bottom-left origin), or
  // std::nullopt where none was drawn by this rasterizer. Valid while that frame's draw set and
  // chunks live.
  std::optional<PointRef> pointAt(int x, int y) const;

 private:
  const ShaderProgram& program(std::uint32_t key, bool resolve);
  void ensureBuffers(int width, int height, bool hq);
  void clearBuffers(bool hq);
  void ensureFlags(std::uint32_t batches);
  void ensureLargeSplats();
  std::uint32_t largeSplatsPerGroup() const;
  void bindBuffers(bool hq) const;

  ComputeRasterizerOptions options_;
  bool atomic64_ = false;
  int cpu_threads_ = 1;  // llvmpipe's threads (1: a GPU; see llvmpipeThreads)
  std::map<std::uint32_t, ShaderProgram> programs_, resolve_programs_;
  // Buffer textures re-pointed at each chunk range: positions, colours, normals, extras, batches,
  // GPS times.
  GLuint textures_[6] = {};
  // Buffer-texture views of the visibility buffer for plain reads: depth keys (or pairs),
  // colours, the four sum planes.
  GLuint views_[6] = {};
  GLuint vao_ = 0;  // empty, for the resolve's full-screen triangle
  // The visibility buffer: depth keys (32-bit path) or (key, id) pairs (64-bit path), ids,
  // packed colours and, for HQ, four planes of colour sums.
  GLuint depths_ = 0, ids_ = 0, colors_ = 0, sums_ = 0;
  GLuint flags_ = 0;  // two uints per invocation of each batch of the frame (see the shader)
  GLuint order_ = 0, order_view_ = 0;  // the batches' order, a uint per batch, and its texture
  GLuint ids_view_ = 0;  // the ids as a buffer texture (pass 2 reads whether a pixel is tied)
  std::uint32_t flag_capacity_ = 0;
  // The large splats' list (the shader's LargeSplats): a header (count, the frame's total, the
  // indirect dispatch's size), then two uvec4 a splat.
  static constexpr GLsizeiptr kLargeHeaderBytes = 32, kLargeSplatBytes = 32;
  static constexpr GLintptr kLargeArgsOffset = 16;
  GLuint large_ = 0;
  std::uint32_t large_capacity_ = 0;
  bool listed_large_splats_ = false;
  bool shared_depth_ = false;                        // the last frame's (sharedDepthOfLastFrame)
  ComputePassTimes pass_times_;                      // the last frame's (passTimesOfLastFrame)
  std::optional<ShaderProgram> large_args_program_;  // the count into the dispatch's size
  float max_point_px_ = 1.0f;
  int width_ = 0, height_ = 0;
  bool has_sums_ = false;
  std::int64_t max_ssbo_bytes_ = 0;
  // The last frame: per draw-set item, its first id and chunk (for pointAt).
  std::vector<std::uint64_t> item_ids_;
  std::vector<const PointChunk*> item_chunks_;
};

}  // namespace parallax
