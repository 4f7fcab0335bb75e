// Parsing of the processing steps (process_steps.h).
#include "process/process_steps.h"

#include <charconv>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace parallax {

namespace {

std::vector<std::string> split(const std::string& text, char separator) {
  std::vector<std::string> parts;
  std::string part;
  std::istringstream in(text);
  while (std::getline(in, part, separator)) parts.push_back(part);
  if (!text.empty() && text.back() == separator) parts.emplace_back();
  return parts;
}

[[noreturn]] void fail(const std::string& step, const std::string& what) {
  throw std::invalid_argument(step + ": " + what);
}

double positiveNumber(const std::string& step, const std::string& name, const std::string& text) {
  double value = 0.0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc() || end != text.data() + text.size() || !std::isfinite(value) ||
      value <= 0.0) {
    fail(step, name + " must be a positive number, got '" + text + "'");
  }
  return value;
}

std::uint64_t wholeNumber(const std::string& step, const std::string& name, const std::string& text,
                          std::uint64_t least, std::uint64_t most) {
  std::uint64_t value = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc() || end != text.data() + text.size() || value < least || value > most) {
    fail(step, name + " must be a whole number from " + std::to_string(least) + " to " +
                   std::to_string(most) + ", got '" + text + "'");
  }
  return value;
}

std::string number(double v) {
  std::ostringstream out;
  out << v;
  return out.str();
}

}  // namespace

NormalsStep parseNormalsK(const std::string& value) {
  NormalsStep step;
  step.k = std::uint32_t(wholeNumber("--normals " + value, "K", value, 3, 1000));
  return step;
}

NormalsStep parseNormalsRadius(const std::string& value) {
  NormalsStep step;
  step.radius = positiveNumber("--normals-radius " + value, "R", value);
  return step;
}

OutliersStep parseOutliers(const std::string& value) {
  const std::string step = "--outliers " + value;
  OutliersStep outliers;
  const auto colon = value.find(':');
  const std::string method = value.substr(0, colon);
  const std::vector<std::string> args =
      colon == std::string::npos ? std::vector<std::string>{} : split(value.substr(colon + 1), ',');
  if (method == "statistical") {
    if (args.size() != 2) fail(step, "expected statistical:K,S (e.g. statistical:8,2)");
    outliers.method = OutliersStep::Method::kStatistical;
    outliers.k = std::uint32_t(wholeNumber(step, "K", args[0], 1, 1000));
    outliers.std_ratio = positiveNumber(step, "S", args[1]);
  } else if (method == "radius") {
    if (args.size() != 2) fail(step, "expected radius:R,N (e.g. radius:0.5,4)");
    outliers.method = OutliersStep::Method::kRadius;
    outliers.radius = positiveNumber(step, "R", args[0]);
    outliers.min_neighbours = std::uint32_t(wholeNumber(step, "N", args[1], 1, 100000));
  } else {
    fail(step, "expected statistical:K,S or radius:R,N, got '" + method + "'");
  }
  return outliers;
}

SubsampleStep parseSubsample(const std::string& value) {
  const std::string step = "--subsample " + value;
  SubsampleStep subsample;
  const auto colon = value.find(':');
  const std::string method = value.substr(0, colon);
  const std::string arg = colon == std::string::npos ? "" : value.substr(colon + 1);
  if (colon == std::string::npos) {
    fail(step, "expected voxel:SIZE, spacing:D or random:N");
  } else if (method == "voxel") {
    subsample.method = SubsampleStep::Method::kVoxel;
    subsample.size = positiveNumber(step, "SIZE", arg);
  } else if (method == "spacing") {
    subsample.method = SubsampleStep::Method::kSpacing;
    subsample.size = positiveNumber(step, "D", arg);
  } else if (method == "random") {
    subsample.method = SubsampleStep::Method::kRandom;
    subsample.count = wholeNumber(step, "N", arg, 0, UINT64_MAX);
  } else {
    fail(step, "expected voxel:SIZE, spacing:D or random:N, got '" + method + "'");
  }
  return subsample;
}

void parseOrientation(const std::string& value, NormalsStep& step) {
  const std::string name = "--orient " + value;
  if (value == "up") {
    step.orientation = NormalOrientation::kUp;
  } else if (value == "sensor") {
    step.orientation = NormalOrientation::kSensor;
  } else if (value == "propagate") {
    step.orientation = NormalOrientation::kPropagate;
  } else {
    const std::vector<std::string> parts = split(value, ',');
    if (parts.size() != 3) fail(name, "expected up, sensor, propagate or X,Y,Z");
    for (int a = 0; a < 3; ++a) {
      const std::string& text = parts[std::size_t(a)];
      double v = 0.0;
      const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), v);
      if (error != std::errc() || end != text.data() + text.size() || !std::isfinite(v)) {
        fail(name, "coordinate " + std::to_string(a + 1) + " must be a number, got '" + text + "'");
      }
      step.toward[a] = v;
    }
    step.orientation = NormalOrientation::kPoint;
  }
}

void parseLocalModel(const std::string& value, DistanceStep& step) {
  if (value != "plane") fail("--local-model " + value, "expected plane");
  step.plane = true;
}

ProcessStep parseProcessStep(const std::string& text) {
  std::vector<std::string> words;
  std::istringstream in(text);
  for (std::string word; in >> word;) {
    words.push_back(word.rfind("--", 0) == 0 ? word.substr(2) : word);
  }
  const auto expected = [&](const std::string& what) {
    fail("processing step '" + text + "'", what);
  };
  if (words.size() < 2) {
    expected(
        "expected a step and its argument: normals K, normals-radius R, outliers "
        "statistical:K,S or radius:R,N, subsample voxel:SIZE, spacing:D or random:N, "
        "distance-to FILE");
  }
  ProcessStep step;
  const std::string& name = words[0];
  if (name == "normals") {
    step = parseNormalsK(words[1]);
  } else if (name == "normals-radius") {
    step = parseNormalsRadius(words[1]);
  } else if (name == "outliers") {
    step = parseOutliers(words[1]);
  } else if (name == "subsample") {
    step = parseSubsample(words[1]);
  } else if (name == "distance-to") {
    DistanceStep distance;
    distance.reference = words[1];
    step = distance;
  } else {
    expected("unknown step '" + name +
             "' (normals, normals-radius, outliers, subsample, distance-to)");
  }
  for (std::size_t i = 2; i < words.size(); ++i) {
    const std::string& option = words[i];
    const bool has_value = i + 1 < words.size();
    auto* normals = std::get_if<NormalsStep>(&step);
    auto* outliers = std::get_if<OutliersStep>(&step);
    auto* distance = std::get_if<DistanceStep>(&step);
    if (normals && option == "curvature") {
      normals->curvature = true;
    } else if (normals && option == "orient" && has_value) {
      parseOrientation(words[++i], *normals);
    } else if (outliers && option == "mark-outliers") {
      outliers->mark = true;
    } else if (distance && option == "local-model" && has_value) {
      parseLocalModel(words[++i], *distance);
    } else if (distance && option == "local-k" && has_value) {
      distance->k =
          std::uint32_t(wholeNumber("--local-k " + words[i + 1], "K", words[i + 1], 3, 1000));
      ++i;
    } else {
      expected("'" + option + "' does not modify a " + name +
               " step (normals: --curvature, --orient X; outliers: --mark-outliers; "
               "distance-to: --local-model plane, --local-k K)");
    }
  }
  return step;
}

std::string describeStep(const ProcessStep& step) {
  if (const auto* n = std::get_if<NormalsStep>(&step)) {
    return n->k ? "--normals " + std::to_string(n->k) : "--normals-radius " + number(n->radius);
  }
  if (const auto* o = std::get_if<OutliersStep>(&step)) {
    if (o->method == OutliersStep::Method::kStatistical) {
      return "--outliers statistical:" + std::to_string(o->k) + "," + number(o->std_ratio);
    }
    return "--outliers radius:" + number(o->radius) + "," + std::to_string(o->min_neighbours);
  }
  if (const auto* s = std::get_if<SubsampleStep>(&step)) {
    switch (s->method) {
      case SubsampleStep::Method::kVoxel:
        return "--subsample voxel:" + number(s->size);
      case SubsampleStep::Method::kSpacing:
        return "--subsample spacing:" + number(s->size);
      case SubsampleStep::Method::kRandom:
        return "--subsample random:" + std::to_string(s->count);
    }
  }
  const auto& d = std::get<DistanceStep>(step);
  return "--distance-to " + d.reference.string() + (d.plane ? " --local-model plane" : "");
}

}  // namespace parallax
