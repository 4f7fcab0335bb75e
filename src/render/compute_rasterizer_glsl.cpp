// GLSL of the compute rasterizer, kept beside the pass (compute_rasterizer.cpp) that binds its
// inputs. See compute_rasterizer.h for the passes and the buffers.
#include "render/compute_rasterizer_glsl.h"

namespace parallax::glsl {

// Variants (ComputeRasterizer prepends the #defines, then pointShadingFunctions()):
//   PASS        1: depth (the atomic step), 2: attributes of the front-most point
//   ATOMIC64    1: one 64-bit atomicMin of (depth key << 32 | id) (GL_NV_shader_atomic_int64);
//               0: 32-bit atomics, depth first, then the id and colour of the front-most point
//   VIEWS       1..4, every point is projected into each view that sees its batch
//   COLOR_MODE, SIZE_MODE, LIGHTING, ORTHOGRAPHIC, FILTER: as in the GL_POINTS pass
//   SPLAT       0: 1-pixel points; 1: square or (ROUND) round splats up to MAX_SPLAT pixels (the
//               largest point GL_POINTS draws): a point's pixels up to INLINE_SPLAT pixels wide
//               are walked by the invocation that reads it
//   LIST_LARGE  1: each pass lists every larger splat (its window position, size, key, id and,
//               in pass 2, colour) in LargeSplats instead; the LARGE program then draws the list
//   LARGE       1: the large-splat program: a workgroup a listed splat, its invocations share its
//               pixels (pass 1: depth, pass 2: attributes, as touchPixel does for any point)
//   HQ          1: pass 2 blends every point within u_hq_range of the front-most one
//   RESET       1: progressive drawing on top of an earlier part: a point that brings a pixel
//               nearer clears what the pixel held (32-bit path: its id, colour and sums)
//   NODE_SPACING 1: adaptive sizes from u_node_spacing alone (every item is an octree node)
//   SHARED_DEPTH 1: every view's clip z and w are view 0's (parallel eyes: off-axis stereo, a
//               headset): a point's depth, its depth key and its near and far tests are computed
//               once, and each view projects only its clip x and y (its own rows of u_mvp)
// No run-time branches on modes: llvmpipe executes both sides of a branch under a mask.
const char* const kComputeRasterizer = R"glsl(#version 450 core
#if ATOMIC64
#extension GL_ARB_gpu_shader_int64 : require
#extension GL_NV_shader_atomic_int64 : require
#endif
// The #defines and the shared colour functions are inserted here.
//@DEFINES@
// 16 invocations of 256 points each (eight flag words, below). Pass 2 runs a vector of 8
// invocations as long as its busiest lane has flagged points left, and over more points the
// busiest lane is nearer the mean; the batch's prologue (its order, box and culling) is paid by
// fewer invocations. CPU time of passes 1 and 2 together, 10 M points at 1080p, shapes run side
// by side: 64 invocations of 64 points 326-404 ms, 32 of 128 317-352 ms, 16 of 256 308-342 ms;
// 8 of 512 was worse than 16 of 256 (317 against 295 ms).
#if LARGE
// A splat of up to 255 x 255 pixels: 64 invocations take consecutive pixels of its rows, so a
// vector of 8 lanes writes 8 neighbouring pixels.
layout(local_size_x = 64) in;
#else
layout(local_size_x = 16) in;
#endif
const uint kPointsPerInvocation = BATCH_POINTS / 16u;

// Point attributes through buffer textures, bound to one range of one chunk: on llvmpipe a
// texel fetch is a vector gather, an SSBO load a loop over the lanes (1.7x the whole pass).
layout(binding = 0) uniform samplerBuffer t_positions;  // RGB32F, chunk-relative
layout(binding = 1) uniform samplerBuffer t_colors;     // RGBA8
layout(binding = 2) uniform usamplerBuffer t_normals;   // R32UI, int 2_10_10_10 (w unused)
layout(binding = 3) uniform usamplerBuffer t_extras;    // RG32UI: intensity | class << 16, spacing
layout(binding = 4) uniform samplerBuffer t_batches;    // RGBA32F, min and max of each batch
layout(binding = 5) uniform samplerBuffer t_gps;        // RG32F, GPS time (hi, lo) (filters)
// The order the frame's workgroups take the batches of each range in, nearest the eye first
// (R32UI, the batch's index in the range, at u_flag_base + workgroup): pass 1 then meets the
// front points early and most points behind them fail the plain depth test, skipping the atomic
// and leaving them unflagged for pass 2.
layout(binding = 7) uniform usamplerBuffer t_batch_order;

// The visibility buffer, one entry per canvas pixel. The depth key is ~bits of the reversed
// window depth (near 1, far 0): smaller is nearer, and the empty value ~0u is the far plane.
#if ATOMIC64
layout(std430, binding = 0) coherent buffer Visibility { uint64_t visibility[]; };
#else
layout(std430, binding = 0) coherent buffer Depths { uint depths[]; };
layout(std430, binding = 1) coherent buffer Ids { uint ids[]; };
// The same depth keys read as a buffer texture: a vector gather on llvmpipe, where an SSBO load
// is a loop over the lanes. Within pass 1 a fetch may see an older, larger key than the atomics
// left (no coherence is promised between the two views): the pre-test below then lets a point
// through to the atomic, which decides, so the result is the same. Pass 2 reads after a barrier.
layout(binding = 6) uniform usamplerBuffer t_depth_keys;
// A pixel's front-most point is nearly always alone at its depth key: pass 2 then stores its id
// and colour with plain writes, no atomic (each atomic is a loop over the lanes on llvmpipe; pass
// 2 of 10 M points at 1080p went from 60 to 55 ms). Pass 1 marks the pixels where two points met
// at equal keys (ids = kTied, beside ~0u for "no tie seen"): there, pass 2 keeps the atomics
// that make ties deterministic. A mark may outlive its tie (a nearer point came later): those
// pixels only take the atomic path. Not for HQ (its sums need atomics) nor RESET (progressive
// parts keep ids of earlier parts).
#define SOLE_WINNER_STORES (!HQ && !RESET)
const uint kTied = TIED_MARK;
#if SOLE_WINNER_STORES
layout(binding = 8) uniform usamplerBuffer t_id_keys;  // the ids: whether a pixel is tied
#endif
#endif
layout(std430, binding = 2) coherent buffer Colors { uint colors[]; };  // packUnorm4x8
// Eight words of flags per invocation of each batch of the frame, a bit per point the invocation
// reads (its k-th point is bit k % 32 of word k / 32): pass 1 sets a point's bit when it was at
// or in front of the stored key when it ran. Every point that ends front-most was, so pass 2
// reads only the flagged points (HQ blends points behind the front too, and reads all). Per point
// rather than per group of points the workgroup reads together: on llvmpipe a vector of 8
// invocations loops as long as one of its lanes has a point left, so pass 2 costs what its most
// flagged lane holds, not every group one flagged point touched (10 M points at 1080p: 19 %
// flagged, pass 2 from 90 to 56 ms).
layout(std430, binding = 7) coherent buffer BatchFlags { uint batch_flags[]; };
uniform uint u_flag_base;  // the range's first batch among the frame's batches (its first slot)
bool may_win = false;

// Splats wider than INLINE_SPLAT pixels, listed by each pass (LIST_LARGE) and drawn by the LARGE
// program: one invocation walking a point's 255 x 255 pixels would hold up the seven other lanes
// of its vector for as long (and run into llvmpipe's limit on an invocation's loop iterations),
// and a workgroup shares them instead. Two uvec4 a splat: (window x, window y, size, depth key)
// as float bits and key, then (id, packed colour, eye depth bits, view). The renderer flushes
// the list (kLargeSplatArgs, then LARGE) before it could hold more than u_large_capacity.
#if LIST_LARGE || LARGE
layout(std430, binding = 8) coherent buffer LargeSplats {
  uint large_count;   // listed since the last flush
  uint large_total;   // listed in the frame (ComputeRasterizer::largeSplatsOfLastFrame)
  uint large_unused[2];
  uvec4 large_args;   // the LARGE dispatch's workgroups (x, y, z) and the splats it draws
  uvec4 large_splats[];
};
uniform uint u_large_capacity;
#endif

// llvmpipe cuts a dispatch into one run of u_run_length consecutive workgroups per thread
// (u_thread_count runs side by side; the rest one at a time after them). Run t's k-th workgroup
// takes slot k * u_thread_count + t, so that the threads walk the batches' front-to-back order
// together (each alone, a thread started in the middle of the order and drew points behind the
// ones the other had not yet drawn) and share pass 2's flagged points, most of them in the
// front batches, evenly. u_run_length 0: the slots in order (a GPU).
uniform uint u_run_length;
uniform uint u_thread_count;
uint slotOf(uint group) {
  if (group >= u_run_length * u_thread_count) return group;
  return (group % u_run_length) * u_thread_count + group / u_run_length;
}

#if HQ
// Sums of the blended colours (0-255 a channel) and their count, one plane each.
layout(std430, binding = 3) coherent buffer SumR { uint sum_r[]; };
layout(std430, binding = 4) coherent buffer SumG { uint sum_g[]; };
layout(std430, binding = 5) coherent buffer SumB { uint sum_b[]; };
layout(std430, binding = 6) coherent buffer SumW { uint sum_w[]; };
#endif

uniform mat4 u_mvp[VIEWS];         // chunk-relative to clip (chunk origin folded in in double)
uniform mat4 u_model_view[VIEWS];  // chunk-relative to eye
uniform vec4 u_viewport[VIEWS];    // x, y, width, height in canvas pixels
uniform float u_pixels_per_unit[VIEWS];
uniform vec4 u_depth_coeffs[VIEWS];  // eye depth from window depth (HQ)
uniform uint u_view_mask;          // views whose frustum meets the chunk's box
uniform int u_canvas_width;
uniform uint u_point_count;  // points in the bound range
uniform uint u_batch_base;   // the range's first batch in the chunk
uniform uint u_id_base;      // the id of the range's first point
uniform vec3 u_uniform_color;
uniform vec2 u_elevation;  // t = (z + x) * y: chunk z to 0..1 over the cloud
uniform float u_size_px;
uniform float u_world_size;
uniform float u_adaptive_scale;
uniform float u_node_spacing;
uniform vec2 u_size_clamp;
uniform float u_hq_range;

// False only when all eight corners are outside one plane of the view's clip volume.
bool boxVisible(mat4 mvp, vec3 lo, vec3 hi) {
  bvec4 all_left = bvec4(true), all_right = bvec4(true);  // x < -w, x > w, y < -w, y > w
  bool all_near = true, all_far = true;                   // z > w, z < 0 (reversed depth)
  for (int c = 0; c < 8; ++c) {
    vec3 corner = vec3((c & 1) != 0 ? hi.x : lo.x, (c & 2) != 0 ? hi.y : lo.y,
                       (c & 4) != 0 ? hi.z : lo.z);
    vec4 q = mvp * vec4(corner, 1.0);
    all_left = bvec4(all_left.x && q.x < -q.w, all_left.y && q.x > q.w, all_left.z && q.y < -q.w,
                     all_left.w && q.y > q.w);
    all_near = all_near && q.z > q.w;
    all_far = all_far && q.z < 0.0;
  }
  return !(any(all_left) || all_near || all_far);
}

uint extras0(uint i) {
  return texelFetch(t_extras, int(i)).x;
}

vec3 normalOf(uint i) {
  int bits = int(texelFetch(t_normals, int(i)).x);
  vec3 n = vec3(bitfieldExtract(bits, 0, 10), bitfieldExtract(bits, 10, 10),
                bitfieldExtract(bits, 20, 10));
  return max(n / 511.0, vec3(-1.0));  // snorm, as the vertex fetch of GL_INT_2_10_10_10_REV
}

// The point's colour in view v, as the GL_POINTS vertex shader computes it.
vec3 pointColor(uint i, vec3 p, int v) {
#if COLOR_MODE == 0
  vec3 color = texelFetch(t_colors, int(i)).rgb;
#elif COLOR_MODE == 1
  vec3 color = ramp((p.z + u_elevation.x) * u_elevation.y);
#elif COLOR_MODE == 2
  vec3 color = vec3(float(extras0(i) & 0xffffu) / 65535.0);
#elif COLOR_MODE == 3
  vec3 color = normalize(normalOf(i)) * 0.5 + 0.5;
#elif COLOR_MODE == 4
  vec3 color = classColor((extras0(i) >> 16) & 0xffu);
#else
  vec3 color = u_uniform_color;
#endif
#if FILTER && FILTER_HIGHLIGHT
  color = highlighted(color, p);
#endif
#if LIGHTING
  vec3 n = normalize(mat3(u_model_view[v]) * normalOf(i));
#if ORTHOGRAPHIC
  vec3 to_eye = vec3(0.0, 0.0, 1.0);
#else
  vec3 to_eye = normalize(-(u_model_view[v] * vec4(p, 1.0)).xyz);
#endif
  color *= 0.2 + 0.8 * abs(dot(n, to_eye));
#endif
  return color;
}

// Point size in pixels in view v, as the GL_POINTS vertex shader computes gl_PointSize.
float pointSize(uint i, vec3 p, int v) {
#if SIZE_MODE == 0
  return u_size_px;
#else
#if SIZE_MODE == 1
  float world = u_world_size;
#elif NODE_SPACING
  // Every item is a level-of-detail node: its spacing, and no fetch of the points' own (a texel
  // fetch is a call on llvmpipe, evaluated even where a select would not use it).
  float world = u_node_spacing * u_adaptive_scale;
#else
  float world = (u_node_spacing > 0.0 ? u_node_spacing
                                      : uintBitsToFloat(texelFetch(t_extras, int(i)).y)) *
                u_adaptive_scale;
#endif
#if ORTHOGRAPHIC
  float per_unit = u_pixels_per_unit[v];
#else
  float eye_z = dot(vec4(u_model_view[v][0].z, u_model_view[v][1].z, u_model_view[v][2].z,
                         u_model_view[v][3].z), vec4(p, 1.0));
  float per_unit = u_pixels_per_unit[v] / max(-eye_z, 1e-9);
#endif
  return world > 0.0 ? clamp(world * per_unit, u_size_clamp.x, u_size_clamp.y) : u_size_px;
#endif
}

#if HQ
float eyeDepthOf(uint key, int v) {
  float z = uintBitsToFloat(~key);
  vec4 k = u_depth_coeffs[v];
  return -(k.y - z * k.w) / (z * k.z - k.x);
}
#endif

// The point's packed colour, computed on first need (most points never need it: they are
// behind). A listed large splat carries its colour from pass 1: always ready.
void needColor(uint i, vec3 p, int v, inout bool ready, inout uint color) {
#if !LARGE
  if (!ready) color = packUnorm4x8(vec4(pointColor(i, p, v), 1.0)), ready = true;
#endif
}

// What one point does to one pixel it covers. `color_ready` and `color` carry the point's colour
// (needColor).
void touchPixel(uint pixel, uint key, uint id, uint i, vec3 p, int v, float eye_depth,
                inout bool color_ready, inout uint color) {
#if PASS == 1
#if ATOMIC64
  uint64_t packed = uint64_t(key) << 32 | uint64_t(id);
  if (packed <= visibility[pixel]) {
    may_win = true;
    atomicMin(visibility[pixel], packed);
  }
#else
  // A plain read first: the stored key only decreases, so a point behind it is behind for good,
  // and most points of a dense cloud skip the atomic.
  uint stored = texelFetch(t_depth_keys, int(pixel)).x;
  if (key <= stored) {
    may_win = true;
#if RESET
    if (key < stored && key < atomicMin(depths[pixel], key)) {
      ids[pixel] = ~0u;
      colors[pixel] = ~0u;
#if HQ
      sum_r[pixel] = 0u, sum_g[pixel] = 0u, sum_b[pixel] = 0u, sum_w[pixel] = 0u;
#endif
    }
#elif SOLE_WINNER_STORES
    // Equal to the stored key, or to what the atomic found there: a tie at this key.
    if (key == stored || key == atomicMin(depths[pixel], key)) ids[pixel] = kTied;
#else
    if (key < stored) atomicMin(depths[pixel], key);
#endif
  }
#endif
#else  // PASS == 2
#if ATOMIC64
  uint front = uint(visibility[pixel] >> 32);
#else
  uint front = texelFetch(t_depth_keys, int(pixel)).x;
#endif
#if HQ
  if (eye_depth <= eyeDepthOf(front, v) * (1.0 + u_hq_range)) {
    needColor(i, p, v, color_ready, color);
    atomicAdd(sum_r[pixel], color & 0xffu);
    atomicAdd(sum_g[pixel], (color >> 8) & 0xffu);
    atomicAdd(sum_b[pixel], (color >> 16) & 0xffu);
    atomicAdd(sum_w[pixel], 1u);
#if !ATOMIC64
    if (key == front) atomicMin(ids[pixel], id);
#endif
  }
#else
#if ATOMIC64
  // The one point whose key won writes its colour: no race, no atomic.
  if (visibility[pixel] == (uint64_t(key) << 32 | uint64_t(id))) {
    needColor(i, p, v, color_ready, color);
    colors[pixel] = color;
  }
#else
  // Exact depth ties: the lowest id and the lowest packed colour win, the same every run.
  if (key == front) {
    needColor(i, p, v, color_ready, color);
#if SOLE_WINNER_STORES
    if (texelFetch(t_id_keys, int(pixel)).x == ~0u) {
      ids[pixel] = id;  // the only point at this key: no other writes the pixel
      colors[pixel] = color;
      return;
    }
#endif
    atomicMin(ids[pixel], id);
    atomicMin(colors[pixel], color);
  }
#endif
#endif
#endif
}

// The pixels whose centres lie inside a point's square of `size` pixels centred at `window`
// (GL's point rule), within view v: from..to inclusive, empty where from > to.
void splatPixels(vec2 window, float size, int v, out ivec2 from, out ivec2 to) {
  vec4 vp = u_viewport[v];
  vec2 first = ceil(window - 0.5 * size - 0.5), last = ceil(window + 0.5 * size - 0.5) - 1.0;
  from = max(ivec2(first), ivec2(vp.xy));
  to = min(ivec2(last), ivec2(vp.xy + vp.zw) - 1);
}

// Round points: whether pixel (x, y)'s centre is inside the disc (GL_POINTS' fragment shader
// discards outside dot(d, d) > 0.25 of gl_PointCoord).
bool insideSplat(int x, int y, vec2 window, float size) {
#if ROUND
  vec2 d = (vec2(x, y) + 0.5 - window) / size;
  return dot(d, d) <= 0.25;
#else
  return true;
#endif
}

#if !LARGE
// A point is clipped by its centre, as GL_POINTS are: here by depth (w > 0, 0 <= z <= w).
bool insideDepth(vec4 clip) {
  return clip.w > 0.0 && clip.z >= 0.0 && clip.z <= clip.w;
}

// The depth key: ~bits of the window depth z / w (inv_w = 1 / w, as the viewport transform
// takes it).
uint depthKey(vec4 clip, float inv_w) {
  return ~(floatBitsToUint(clip.z * inv_w) & 0x7fffffffu);
}

// `first_clip`, `first_inv_w` and `first_key`: view 0's clip position, 1 / w and depth key
// (SHARED_DEPTH only, where every view has them; the point is inside the views' depth range).
void drawInView(uint i, uint id, vec3 p, int v, vec4 first_clip, float first_inv_w,
                uint first_key) {
#if SHARED_DEPTH
  // x and y as the whole product computes them (the rest is left unused), so the pixels are
  // those of the view projected alone; z and w are view 0's, the same floats.
  vec4 clip = vec4((u_mvp[v] * vec4(p, 1.0)).xy, first_clip.zw);
  if (!(abs(clip.x) <= clip.w && abs(clip.y) <= clip.w)) return;
  float inv_w = first_inv_w;
  uint key = first_key;
#else
  vec4 clip = u_mvp[v] * vec4(p, 1.0);
  if (!(insideDepth(clip) && abs(clip.x) <= clip.w && abs(clip.y) <= clip.w)) return;
  // The viewport transform as the GL pipeline does it (a reciprocal of w, then scale and
  // translate).
  float inv_w = 1.0 / clip.w;
  uint key = depthKey(clip, inv_w);
#endif
  // Snapped to llvmpipe's 1/256 pixel, so that both rasterizers light the same pixel.
  vec4 vp = u_viewport[v];
  vec2 window = clip.xy * inv_w * (0.5 * vp.zw) + (vp.xy + 0.5 * vp.zw);
  window = floor(window * 256.0 + 0.5) / 256.0;
#if HQ
  vec4 eye = u_model_view[v] * vec4(p, 1.0);
  float eye_depth = -eye.z;
#else
  float eye_depth = 0.0;
#endif
  bool color_ready = false;
  uint color = 0u;
#if SPLAT
  float size = min(pointSize(i, p, v), MAX_SPLAT);
#if LIST_LARGE
  if (size > INLINE_SPLAT) {
    // Pass 1 cannot tell here whether the splat wins a pixel: it is flagged, so that pass 2
    // lists it again (with its colour).
    may_win = true;
#if PASS == 2
    needColor(i, p, v, color_ready, color);
#endif
    uint slot = atomicAdd(large_count, 1u);
    // The renderer's groups of ranges keep the list within its capacity; the test only guards
    // the buffer's end.
    if (slot < u_large_capacity) {
      large_splats[2u * slot] = uvec4(floatBitsToUint(window), floatBitsToUint(size), key);
      large_splats[2u * slot + 1u] = uvec4(id, color, floatBitsToUint(eye_depth), uint(v));
    }
    return;
  }
#endif
  ivec2 from, to;
  splatPixels(window, size, v, from, to);
  for (int y = from.y; y <= to.y; ++y) {
    for (int x = from.x; x <= to.x; ++x) {
      if (!insideSplat(x, y, window, size)) continue;
      touchPixel(uint(y) * uint(u_canvas_width) + uint(x), key, id, i, p, v, eye_depth,
                 color_ready, color);
    }
  }
#else
  ivec2 q = ivec2(ceil(window - 1.0));
  ivec2 low = ivec2(vp.xy), high = ivec2(vp.xy + vp.zw) - 1;
  if (any(lessThan(q, low)) || any(greaterThan(q, high))) return;
  touchPixel(uint(q.y) * uint(u_canvas_width) + uint(q.x), key, id, i, p, v, eye_depth,
             color_ready, color);
#endif
}

// Point `i` of the bound range, drawn into every view that sees its batch; true where it was at
// or in front of a pixel's stored key (pass 1: it may end front-most).
bool drawPoint(uint i, uint views) {
  vec3 p = texelFetch(t_positions, int(i)).xyz;
#if FILTER
#if FILTER_GPS
  vec2 gps = texelFetch(t_gps, int(i)).xy;
#else
  vec2 gps = vec2(0.0);
#endif
#if FILTER_CLASSES || FILTER_RETURNS || FILTER_INTENSITY
  uint word = extras0(i);
#else
  uint word = 0u;  // the extras are not bound: no test reads them
#endif
  if (!keepPoint(p, word, gps)) return false;
#endif
  may_win = false;
  // Read once, drawn into every view (stereo in one pass); with SHARED_DEPTH its depth
  // projected once too.
#if SHARED_DEPTH
  vec4 first_clip = u_mvp[0] * vec4(p, 1.0);
  if (!insideDepth(first_clip)) return false;
  float first_inv_w = 1.0 / first_clip.w;
  uint first_key = depthKey(first_clip, first_inv_w);
#else
  vec4 first_clip = vec4(0.0);
  float first_inv_w = 0.0;
  uint first_key = 0u;
#endif
  // Each view written out with its index a constant, not a loop over the views: llvmpipe runs an
  // if's body for every lane (masked) and a loop while any lane goes on, and a loop over the views
  // indexed its uniforms with a variable. With the loop, a stereo frame's pass 1 cost 3.0-3.6x
  // mono's (CPU, the 2 M-point demo in view's look at 2 x 1440x1600), and one eye alone in the
  // two-view program (the other masked off) 3-4x mono: the program, not the second eye's
  // pixels. Written out: 1.5-2.5x (xr NOTES, "The second eye").
#define DRAW_IN_VIEW(v)                                                                 \
  if ((views & (1u << v)) != 0u) {                                                      \
    drawInView(i, u_id_base + i, p, v, first_clip, first_inv_w, first_key);             \
  }
  DRAW_IN_VIEW(0)
#if VIEWS > 1
  DRAW_IN_VIEW(1)
#endif
#if VIEWS > 2
  DRAW_IN_VIEW(2)
#endif
#if VIEWS > 3
  DRAW_IN_VIEW(3)
#endif
#undef DRAW_IN_VIEW
  return may_win;
}

void main() {
  uint slot = u_flag_base + slotOf(gl_WorkGroupID.x);
  uint range_batch = texelFetch(t_batch_order, int(slot)).x;
  // This invocation's flags (see BatchFlags): one bit for each of its 256 points.
  uint flag_word = 8u * (gl_WorkGroupSize.x * slot + gl_LocalInvocationID.x);
#if PASS == 2 && !HQ
  uvec4 todo_low = uvec4(batch_flags[flag_word], batch_flags[flag_word + 1u],
                         batch_flags[flag_word + 2u], batch_flags[flag_word + 3u]);
  uvec4 todo_high = uvec4(batch_flags[flag_word + 4u], batch_flags[flag_word + 5u],
                          batch_flags[flag_word + 6u], batch_flags[flag_word + 7u]);
  if (todo_low == uvec4(0u) && todo_high == uvec4(0u)) return;
#endif
  // The batch is culled against every view before any of its points is read.
  uint batch = u_batch_base + range_batch;
  vec3 lo = texelFetch(t_batches, int(2u * batch)).xyz;
  vec3 hi = texelFetch(t_batches, int(2u * batch + 1u)).xyz;
  uint views = 0u;
  for (int v = 0; v < VIEWS; ++v) {
    if (((u_view_mask >> v) & 1u) != 0u && boxVisible(u_mvp[v], lo, hi)) views |= 1u << v;
  }
  if (views == 0u) return;
  // The invocation's points are `first` and every gl_WorkGroupSize.x-th after it, so that a
  // vector's lanes read consecutive points.
  uint first = range_batch * BATCH_POINTS + gl_LocalInvocationID.x;
#if PASS == 2 && !HQ
  // Only the flagged points, by a loop over the set bits rather than a test in a loop over all:
  // llvmpipe runs a masked-off body all the same, but leaves a loop once no lane goes on.
  // The words are named one by one: a loop counter indexing an array is a vector on llvmpipe.
  while (todo_low != uvec4(0u) || todo_high != uvec4(0u)) {
    uint k;
#define TAKE_LOWEST_BIT(word, first_bit) \
  if (word != 0u) {                      \
    k = first_bit + uint(findLSB(word)); \
    word &= word - 1u;                   \
  } else
    TAKE_LOWEST_BIT(todo_low.x, 0u)
    TAKE_LOWEST_BIT(todo_low.y, 32u)
    TAKE_LOWEST_BIT(todo_low.z, 64u)
    TAKE_LOWEST_BIT(todo_low.w, 96u)
    TAKE_LOWEST_BIT(todo_high.x, 128u)
    TAKE_LOWEST_BIT(todo_high.y, 160u)
    TAKE_LOWEST_BIT(todo_high.z, 192u) {
      k = 224u + uint(findLSB(todo_high.w));
      todo_high.w &= todo_high.w - 1u;
    }
    uint i = first + k * gl_WorkGroupSize.x;
    if (i >= u_point_count) break;
    drawPoint(i, views);
  }
#else
  // A word of flags at a time, each kept in one register and stored once.
  for (uint word = 0u; word < kPointsPerInvocation / 32u; ++word) {
    uint won = 0u;
    for (uint bit = 0u; bit < 32u; ++bit) {
      uint i = first + (32u * word + bit) * gl_WorkGroupSize.x;
      if (i >= u_point_count) break;
      if (drawPoint(i, views)) won |= 1u << bit;
    }
#if PASS == 1
    // The invocation's own word: no other writes it, no atomic needed.
    if (won != 0u) batch_flags[flag_word + word] = won;
#endif
  }
#endif
}
#else  // LARGE
// A workgroup takes LARGE_SPLATS_PER_GROUP listed splats one after the other, its invocations
// taking consecutive pixels of each one's rows: the same touchPixel, key, id and colour as the
// point would have had drawn inline, so the picture does not depend on which way a splat went.
// Several splats a workgroup, because llvmpipe spends about 4 us on a workgroup whatever it
// draws; not more, because an invocation's loops stop after 65 535 iterations in all there
// (64 splats of 255 x 255 pixels: 64 x 1 017).
void main() {
  uint group = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
  uint last = min(min(large_args.w, u_large_capacity), (group + 1u) * LARGE_SPLATS_PER_GROUP);
  for (uint s = group * LARGE_SPLATS_PER_GROUP; s < last; ++s) {
    uvec4 a = large_splats[2u * s], b = large_splats[2u * s + 1u];
    vec2 window = uintBitsToFloat(a.xy);
    float size = uintBitsToFloat(a.z);
    int v = int(b.w);
    ivec2 from, to;
    splatPixels(window, size, v, from, to);
    if (any(greaterThan(from, to))) continue;
    uint row = uint(to.x - from.x + 1), pixels = row * uint(to.y - from.y + 1);
    bool color_ready = true;
    uint color = b.y;
    for (uint k = gl_LocalInvocationID.x; k < pixels; k += gl_WorkGroupSize.x) {
      int x = from.x + int(k % row), y = from.y + int(k / row);
      if (!insideSplat(x, y, window, size)) continue;
      touchPixel(uint(y) * uint(u_canvas_width) + uint(x), a.w, b.x, 0u, vec3(0.0), v,
                 uintBitsToFloat(b.z), color_ready, color);
    }
  }
}
#endif
)glsl";

// The large splats listed since the last flush into the size of the LARGE program's indirect
// dispatch (a workgroup for 64 splats, rows of at most 65 535 workgroups), added to the frame's
// total
// in pass 1 (pass 2 lists the flagged ones again), and the count back to 0 for the next ranges. One invocation: the count is read on the GPU,
// never waited for on the CPU.
const char* const kLargeSplatArgs = R"glsl(#version 450 core
layout(local_size_x = 1) in;
layout(std430, binding = 8) coherent buffer LargeSplats {
  uint large_count;
  uint large_total;
  uint large_unused[2];
  uvec4 large_args;
};
uniform uint u_pass;
void main() {
  uint n = large_count;
  if (u_pass == 1u) large_total += n;
  uint groups = (n + 63u) / 64u;  // LARGE_SPLATS_PER_GROUP
  large_args = uvec4(min(groups, 65535u), (groups + 65534u) / 65535u, 1u, n);
  large_count = 0u;
}
)glsl";

// Writes the visibility buffer into the framebuffer: colour, eye depth for eye-dome lighting,
// and depth, drawn per view over a full-screen triangle. Empty pixels are discarded (the
// background stays); the depth test GEQUAL keeps a nearer point the GL_POINTS fall-back drew.
const char* const kComputeResolve = R"glsl(#version 450 core
//@DEFINES@
// Read-only views of the visibility buffer (buffer textures: gathers on llvmpipe).
layout(binding = 0) uniform usamplerBuffer t_depths;  // R32UI keys; 64-bit path: RG32UI (id, key)
layout(binding = 1) uniform usamplerBuffer t_colors;  // R32UI, packUnorm4x8
#if HQ
layout(binding = 2) uniform usamplerBuffer t_sum_r;
layout(binding = 3) uniform usamplerBuffer t_sum_g;
layout(binding = 4) uniform usamplerBuffer t_sum_b;
layout(binding = 5) uniform usamplerBuffer t_sum_w;
#endif
uniform int u_canvas_width;
uniform vec4 u_depth_coeffs;  // z_clip = x z_eye + y, w_clip = z z_eye + w
layout(location = 0) out vec4 out_color;
#if EYE_DEPTH
layout(location = 1) out vec2 out_depth;
#endif

void main() {
  ivec2 q = ivec2(gl_FragCoord.xy);
  int pixel = q.y * u_canvas_width + q.x;
#if ATOMIC64
  uint key = texelFetch(t_depths, pixel).y;
#else
  uint key = texelFetch(t_depths, pixel).x;
#endif
  if (key == ~0u) discard;
  float z = uintBitsToFloat(~key);
  gl_FragDepth = z;
#if HQ
  float weight = float(max(texelFetch(t_sum_w, pixel).x, 1u));
  vec3 color = vec3(texelFetch(t_sum_r, pixel).x, texelFetch(t_sum_g, pixel).x,
                    texelFetch(t_sum_b, pixel).x) / (255.0 * weight);
#else
  vec3 color = unpackUnorm4x8(texelFetch(t_colors, pixel).x).rgb;
#endif
  out_color = vec4(color, 1.0);
#if EYE_DEPTH
  float eye_z =
      (u_depth_coeffs.y - z * u_depth_coeffs.w) / (z * u_depth_coeffs.z - u_depth_coeffs.x);
#if ORTHOGRAPHIC
  out_depth = vec2(-eye_z, 1.0);
#else
  out_depth = vec2(max(-eye_z, 0.0), 1.0);
#endif
#endif
}
)glsl";

}  // namespace parallax::glsl
