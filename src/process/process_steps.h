// The steps of `parallax process`, as given on the command line, and their parsing.
//
// Each step is one value of ProcessStep; the runner (process_runner.h) runs them in the order
// given, each on the points the steps before it kept. Parsing throws std::invalid_argument whose
// message starts with the step's option ("--outliers statistical:K,S: S must be ...").
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <variant>
#include <vector>

#include "terrain/csf.h"
#include "terrain/pmf.h"
#include "terrain/smrf.h"

namespace parallax {

enum class NormalOrientation {
  kUp,      // towards +z
  kPoint,   // towards a point (`toward`)
  kSensor,  // towards the scanner position the points carry
  kPropagate,
};

struct NormalsStep {
  std::uint32_t k = 0;  // K nearest neighbours (the point itself included); 0: by radius
  double radius = 0.0;  // every neighbour within this radius, when k == 0
  bool curvature = false;
  NormalOrientation orientation = NormalOrientation::kUp;
  double toward[3] = {0, 0, 0};
};

struct OutliersStep {
  enum class Method { kStatistical, kRadius } method = Method::kStatistical;
  std::uint32_t k = 0;     // statistical: neighbours averaged (the point itself not counted)
  double std_ratio = 0.0;  // statistical: S
  double radius = 0.0;     // radius: R
  std::uint32_t min_neighbours = 0;  // radius: N (the point itself not counted)
  bool mark = false;                 // class 7 (low noise) instead of removal
};

struct SubsampleStep {
  enum class Method { kVoxel, kSpacing, kRandom } method = Method::kVoxel;
  double size = 0.0;        // voxel edge, or the least spacing
  std::uint64_t count = 0;  // random: points kept
};

struct DistanceStep {
  std::filesystem::path reference;
  bool plane = false;   // --local-model plane: to the plane of the K nearest reference points
  std::uint32_t k = 6;  // neighbours of the local model
};

// --ground: a whole-cloud grid step (terrain/): class 2 (ground) or 1 (the rest) for every kept
// point, or with --keep-classes for those of class 0 or 1 only.
struct GroundStep {
  enum class Method { kSmrf, kPmf, kCsf } method = Method::kSmrf;
  SmrfParameters smrf;
  PmfParameters pmf;
  CsfParameters csf;
  bool keep_classes = false;
};

// --height-above-ground: `height_above_ground` (float), z less the height of the 2D Delaunay
// triangulation of the ground points (class 2 so far: the input's or an earlier --ground's) at
// the point's x y; outside the ground's convex hull, less the nearest ground point's z.
struct HeightAboveGroundStep {};

// --m3c2 EPOCH2 (Lague, Brodu & Leroux 2013, "Accurate 3D comparison of complex topography with
// terrestrial laser scanner"): for each core point (the processed cloud's kept points) the change
// from epoch 1 to epoch 2 along the local normal, measured inside a cylinder, and its level of
// detection. Distances in the points' world units. step_m3c2.cpp; NOTES.md "M3C2".
struct M3c2Step {
  std::filesystem::path epoch2;
  // Epoch 1 when the processed cloud is only the core points (--core-points): read as another
  // cloud. Empty: epoch 1 is the processed cloud's kept points themselves.
  std::vector<std::filesystem::path> epoch1;
  double normal_scale = 0.0;        // D, the paper's normal scale: a diameter (PCA within D / 2)
  double cylinder_radius = 0.0;     // R (the paper's d is the diameter 2R)
  double half_length = 0.0;         // H: the cylinder reaches H either side of the core point
  double registration_error = 0.0;  // reg, added to the level of detection
  bool median = false;              // medians of the projections instead of means
  // kUp or kPoint (`toward`): the normal's sign, hence the distance's.
  NormalOrientation orientation = NormalOrientation::kUp;
  double toward[3] = {0, 0, 0};
};

using ProcessStep = std::variant<NormalsStep, OutliersStep, SubsampleStep, DistanceStep, GroundStep,
                                 HeightAboveGroundStep, M3c2Step>;

// "--normals 16", "--outliers statistical:8,2", ...: how the step was asked for (messages).
std::string describeStep(const ProcessStep& step);

// One step as its command-line options read, in describeStep()'s words: the step's option and
// its argument ("--normals 16", "--outliers statistical:8,2", "--subsample voxel:0.1",
// "--distance-to ref.las", "--normals-radius 0.5"; the leading dashes may be left out), then
// the options that modify it ("--curvature", "--orient X", "--mark-outliers", "--local-model
// plane", "--local-k K"), separated by spaces. For the viewer's Processing panel, where a step
// is typed on one line. Throws std::invalid_argument naming the step and what was expected.
ProcessStep parseProcessStep(const std::string& text);

// `value` is the option's argument as typed.
NormalsStep parseNormalsK(const std::string& value);
NormalsStep parseNormalsRadius(const std::string& value);
OutliersStep parseOutliers(const std::string& value);
SubsampleStep parseSubsample(const std::string& value);
// "smrf" or "smrf:cell=1,slope=0.15,window=18,scalar=1.25,threshold=0.5" (any of the keys, in
// any order; the others keep PDAL's defaults); "pmf" or "pmf:max_window_size=33,slope=0.7,
// initial_distance=0.15,max_distance=10,cell_size=1,base=2,exponential=true" (PCL's names and
// defaults); "csf" or "csf:resolution=0.5,rigidness=3,iterations=500,time_step=0.65,
// class_threshold=0.5,slope_smoothing=true" (the CSF library's names and defaults).
GroundStep parseGround(const std::string& value);
// "up", "sensor", "propagate" or "X,Y,Z"; applied to `step`.
void parseOrientation(const std::string& value, NormalsStep& step);
// Checks an M3C2 step's parameters (each positive and finite, reg not negative, orientation up or
// towards a point): std::invalid_argument naming the step.
void checkM3c2(const M3c2Step& step);
// "plane"; applied to `step`.
void parseLocalModel(const std::string& value, DistanceStep& step);

}  // namespace parallax
