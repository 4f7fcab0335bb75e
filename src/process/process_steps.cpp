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

GroundStep parseGround(const std::string& value) {
  const std::string step = "--ground " + value;
  GroundStep ground;
  const auto colon = value.find(':');
  const std::string method = value.substr(0, colon);
  if (method != "smrf" && method != "pmf" && method != "csf") {
    fail(step, "expected smrf[:key=value,...], pmf[:key=value,...] or csf[:key=value,...], got '" +
                   method + "'");
  }
  ground.method = method == "smrf"  ? GroundStep::Method::kSmrf
                  : method == "pmf" ? GroundStep::Method::kPmf
                                    : GroundStep::Method::kCsf;
  if (colon == std::string::npos) return ground;
  const std::string keys = method == "smrf" ? "cell, slope, window, scalar, threshold"
                           : method == "pmf"
                               ? "max_window_size, slope, initial_distance, max_distance, "
                                 "cell_size, base, exponential"
                               : "resolution, rigidness, iterations, time_step, class_threshold, "
                                 "slope_smoothing";
  SmrfParameters& p = ground.smrf;
  PmfParameters& m = ground.pmf;
  for (const std::string& pair : split(value.substr(colon + 1), ',')) {
    const auto equals = pair.find('=');
    if (equals == std::string::npos) {
      fail(step, "expected key=value (" + keys + "), got '" + pair + "'");
    }
    const std::string key = pair.substr(0, equals), text = pair.substr(equals + 1);
    if (method == "csf") {
      CsfParameters& c = ground.csf;
      if (key == "resolution") {
        c.resolution = positiveNumber(step, key, text);
      } else if (key == "rigidness") {
        c.rigidness = int(wholeNumber(step, key, text, 1, 3));
      } else if (key == "iterations") {
        c.iterations = int(wholeNumber(step, key, text, 1, 100000));
      } else if (key == "time_step") {
        c.time_step = positiveNumber(step, key, text);
      } else if (key == "class_threshold") {
        c.class_threshold = positiveNumber(step, key, text);
      } else if (key == "slope_smoothing") {
        if (text != "true" && text != "false") {
          fail(step, "slope_smoothing must be true or false, got '" + text + "'");
        }
        c.slope_smoothing = text == "true";
      } else {
        fail(step, "unknown key '" + key + "' (csf takes " + keys + ")");
      }
      continue;
    }
    if (method == "pmf") {
      if (key == "max_window_size") {
        m.max_window_size = positiveNumber(step, key, text);
      } else if (key == "slope") {
        m.slope = positiveNumber(step, key, text);
      } else if (key == "initial_distance") {
        m.initial_distance = positiveNumber(step, key, text);
      } else if (key == "max_distance") {
        m.max_distance = positiveNumber(step, key, text);
      } else if (key == "cell_size") {
        m.cell_size = positiveNumber(step, key, text);
      } else if (key == "base") {
        m.base = positiveNumber(step, key, text);
        if (m.base <= 1.0) fail(step, "base must be above 1, got '" + text + "'");
      } else if (key == "exponential") {
        if (text != "true" && text != "false") {
          fail(step, "exponential must be true or false, got '" + text + "'");
        }
        m.exponential = text == "true";
      } else {
        fail(step, "unknown key '" + key + "' (pmf takes " + keys + ")");
      }
      continue;
    }
    if (key == "cell") {
      p.cell = positiveNumber(step, "cell", text);
    } else if (key == "slope") {
      p.slope = positiveNumber(step, "slope", text);
    } else if (key == "window") {
      p.window = positiveNumber(step, "window", text);
    } else if (key == "scalar") {
      p.scalar = text == "0" ? 0.0 : positiveNumber(step, "scalar", text);
    } else if (key == "threshold") {
      p.threshold = positiveNumber(step, "threshold", text);
    } else {
      fail(step, "unknown key '" + key + "' (smrf takes " + keys + ")");
    }
  }
  return ground;
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

void checkM3c2(const M3c2Step& step) {
  const std::string name = "--m3c2 " + step.epoch2.string();
  auto positive = [&](double v, const std::string& what) {
    if (!std::isfinite(v) || v <= 0.0) {
      fail(name, what + " must be a positive number, got " + number(v));
    }
  };
  positive(step.normal_scale, "--normal-radius D (the normal scale, a diameter)");
  positive(step.cylinder_radius, "--cylinder-radius R");
  positive(step.half_length, "--cylinder-half-length H");
  if (!std::isfinite(step.registration_error) || step.registration_error < 0.0) {
    fail(name, "--registration-error must be a number of at least 0, got " +
                   number(step.registration_error));
  }
  if (step.orientation != NormalOrientation::kUp && step.orientation != NormalOrientation::kPoint) {
    fail(name,
         "the normals' orientation must be up or X,Y,Z (sensor and propagate are for "
         "--normals)");
  }
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
  // The one step without an argument: its options start at the second word.
  const bool argument = words.empty() || words[0] != "height-above-ground";
  if (words.size() < (argument ? 2u : 1u)) {
    expected(
        "expected a step and its argument: normals K, normals-radius R, outliers "
        "statistical:K,S or radius:R,N, subsample voxel:SIZE, spacing:D or random:N, "
        "distance-to FILE, ground smrf|pmf|csf[:KEY=VALUE,...], height-above-ground");
  }
  ProcessStep step;
  const std::string& name = words[0];
  if (name == "height-above-ground") {
    step = HeightAboveGroundStep{};
  } else if (name == "ground") {
    step = parseGround(words[1]);
  } else if (name == "normals") {
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
             "' (normals, normals-radius, outliers, subsample, distance-to, ground, "
             "height-above-ground)");
  }
  for (std::size_t i = argument ? 2 : 1; i < words.size(); ++i) {
    const std::string& option = words[i];
    const bool has_value = i + 1 < words.size();
    auto* normals = std::get_if<NormalsStep>(&step);
    auto* outliers = std::get_if<OutliersStep>(&step);
    auto* distance = std::get_if<DistanceStep>(&step);
    auto* ground = std::get_if<GroundStep>(&step);
    if (normals && option == "curvature") {
      normals->curvature = true;
    } else if (normals && option == "orient" && has_value) {
      parseOrientation(words[++i], *normals);
    } else if (ground && option == "keep-classes") {
      ground->keep_classes = true;
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
               "distance-to: --local-model plane, --local-k K; ground: --keep-classes)");
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
  if (std::holds_alternative<HeightAboveGroundStep>(step)) return "--height-above-ground";
  if (const auto* g = std::get_if<GroundStep>(&step)) {
    const std::string keep = g->keep_classes ? " --keep-classes" : "";
    if (g->method == GroundStep::Method::kCsf) {
      const CsfParameters& c = g->csf;
      return "--ground csf:resolution=" + number(c.resolution) +
             ",rigidness=" + std::to_string(c.rigidness) +
             ",iterations=" + std::to_string(c.iterations) + ",time_step=" + number(c.time_step) +
             ",class_threshold=" + number(c.class_threshold) +
             ",slope_smoothing=" + (c.slope_smoothing ? "true" : "false") + keep;
    }
    if (g->method == GroundStep::Method::kPmf) {
      const PmfParameters& m = g->pmf;
      return "--ground pmf:max_window_size=" + number(m.max_window_size) +
             ",slope=" + number(m.slope) + ",initial_distance=" + number(m.initial_distance) +
             ",max_distance=" + number(m.max_distance) + ",cell_size=" + number(m.cell_size) +
             ",base=" + number(m.base) + ",exponential=" + (m.exponential ? "true" : "false") +
             keep;
    }
    const SmrfParameters& p = g->smrf;
    return "--ground smrf:cell=" + number(p.cell) + ",slope=" + number(p.slope) +
           ",window=" + number(p.window) + ",scalar=" + number(p.scalar) +
           ",threshold=" + number(p.threshold) + keep;
  }
  if (const auto* m = std::get_if<M3c2Step>(&step)) return "--m3c2 " + m->epoch2.string();
  const auto& d = std::get<DistanceStep>(step);
  return "--distance-to " + d.reference.string() + (d.plane ? " --local-model plane" : "");
}

}  // namespace parallax
