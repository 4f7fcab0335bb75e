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

using ProcessStep = std::variant<NormalsStep, OutliersStep, SubsampleStep, DistanceStep>;

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
// "up", "sensor", "propagate" or "X,Y,Z"; applied to `step`.
void parseOrientation(const std::string& value, NormalsStep& step);
// "plane"; applied to `step`.
void parseLocalModel(const std::string& value, DistanceStep& step);

}  // namespace parallax
