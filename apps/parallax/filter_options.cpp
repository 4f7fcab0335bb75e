#include "filter_options.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <optional>
#include <stdexcept>

#include "io/polygon_reader.h"

namespace parallax::cli {
namespace {

std::string_view trimmed(std::string_view text) {
  while (!text.empty() && text.front() == ' ') text.remove_prefix(1);
  while (!text.empty() && text.back() == ' ') text.remove_suffix(1);
  return text;
}

// The comma-separated items of a list, without surrounding blanks ("2, 6" as a shell user may
// quote it), empty ones included (so that "2,,3" is reported, not read as "2,3").
std::vector<std::string_view> splitItems(std::string_view text) {
  std::vector<std::string_view> items;
  for (std::size_t start = 0;;) {
    const std::size_t comma = text.find(',', start);
    items.push_back(
        trimmed(text.substr(start, comma == std::string_view::npos ? comma : comma - start)));
    if (comma == std::string_view::npos) return items;
    start = comma + 1;
  }
}

std::string quotedItem(std::string_view item) {
  std::string text = "'";
  text += item;
  text += '\'';
  return text;
}

// A whole item as a class number, or -1.
int classNumber(std::string_view text) {
  int value = -1;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc{} || end != text.data() + text.size() || text.empty()) return -1;
  return value >= 0 && value <= 255 ? value : -1;
}

// A whole item as a finite double ("+" allowed), or nothing.
std::optional<double> numberOf(std::string_view item) {
  const char* begin = item.data();
  if (!item.empty() && item.front() == '+') ++begin;  // from_chars takes no plus sign
  double value = 0.0;
  const auto [end, error] = std::from_chars(begin, item.data() + item.size(), value);
  if (item.empty() || error != std::errc{} || end != item.data() + item.size() ||
      !std::isfinite(value)) {
    return std::nullopt;
  }
  return value;
}

constexpr const char* kReturnsExpected =
    "expected first, last, intermediate, single, multiple, a return number 1-15 or a range N-M "
    "(e.g. --returns first,last or --returns 1,2)";

constexpr std::pair<const char*, ReturnKind> kReturnKinds[] = {
    {"first", ReturnKind::First},
    {"last", ReturnKind::Last},
    {"intermediate", ReturnKind::Intermediate},
    {"single", ReturnKind::Single},
    {"multiple", ReturnKind::Multiple},
};

// A whole item as a return number 1-15, or -1.
int returnNumber(std::string_view text) {
  int value = -1;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc{} || end != text.data() + text.size() || text.empty()) return -1;
  return value >= 1 && value <= 15 ? value : -1;
}

constexpr const char* kClassesExpected =
    "expected a class number 0-255 or a range N-M such as 9-12 (e.g. --classes 2,6,9-12)";

}  // namespace

void addFilterOptions(CLI::App& command, FilterOptions& o, const std::string& what) {
  // An empty value would read as "not given" (keep everything): refused where it is parsed.
  const auto not_empty = [](const std::string& value) {
    return value.empty() ? std::string("expected a list, found an empty value") : std::string();
  };
  command
      .add_option("--classes", o.classes,
                  "ASPRS classes (0-255) and ranges, e.g. 2,6,9-12: only points of these are " +
                      what + " (points without classification are class 0)")
      ->check(not_empty);
  command
      .add_option("--returns", o.returns,
                  "first, last, intermediate, single, multiple and return numbers 1-15, e.g. "
                  "first,last or 1,2: only points that are any of these are " +
                      what + " (points without returns are return 1 of 1)")
      ->check(not_empty);
  command
      .add_option("--intensity", o.intensity,
                  "MIN,MAX: only points of intensity in [MIN, MAX] are " + what +
                      " (points without intensity have 0)")
      ->check(not_empty);
  command
      .add_option("--elevation", o.elevation,
                  "MIN,MAX: only points of world z in [MIN, MAX] are " + what)
      ->check(not_empty);
  command
      .add_option("--gps-time", o.gps_time,
                  "MIN,MAX: only points of GPS time in [MIN, MAX] are " + what +
                      " (points without GPS time have 0)")
      ->check(not_empty);
  command
      .add_option("--clip-box", o.clip_box,
                  "XMIN,YMIN,ZMIN,XMAX,YMAX,ZMAX[,YAW] in world coordinates: only points "
                  "inside the box are " +
                      what +
                      " (see --clip-mode); YAW turns it by that many degrees about the vertical "
                      "line through its centre, counter-clockwise seen from above")
      ->check(not_empty);
  command
      .add_option("--clip-polygon", o.clip_polygon,
                  "a polygon file (GeoJSON Polygon, Feature or FeatureCollection of one, or "
                  "'x y' lines) in the cloud's x, y: only points inside it, along all z, are " +
                      what + "; with --clip-box, inside both (see --clip-mode)")
      ->check(not_empty);
  command.add_option("--clip-mode", o.clip_mode,
                     "inside (default): keep the --clip-box's / --clip-polygon's content; "
                     "outside: hide it, keep the rest; highlight (render, view): keep every "
                     "point and tint the content");
}

std::vector<int> parseClassList(std::string_view text) {
  std::vector<int> classes;
  for (const std::string_view item : splitItems(text)) {
    const std::size_t dash = item.find('-', 1);  // not a leading minus: "-3" is no class
    if (dash == std::string_view::npos) {
      const int c = classNumber(item);
      if (c < 0) {
        throw std::invalid_argument("--classes: item " + quotedItem(item) +
                                    " is not a class: " + kClassesExpected);
      }
      classes.push_back(c);
      continue;
    }
    const int first = classNumber(item.substr(0, dash)), last = classNumber(item.substr(dash + 1));
    if (first < 0 || last < 0) {
      throw std::invalid_argument("--classes: item " + quotedItem(item) +
                                  " is not a range: " + kClassesExpected);
    }
    if (first > last) {
      throw std::invalid_argument("--classes: range " + quotedItem(item) +
                                  " runs backwards: expected N-M with N <= M (write " +
                                  std::to_string(last) + "-" + std::to_string(first) + ")");
    }
    for (int c = first; c <= last; ++c) classes.push_back(c);
  }
  return classes;
}

ClipBox parseClipBox(std::string_view text) {
  static constexpr std::array<const char*, 7> kNames{"XMIN", "YMIN", "ZMIN", "XMAX",
                                                     "YMAX", "ZMAX", "YAW"};
  const std::vector<std::string_view> items = splitItems(text);
  if (items.size() != 6 && items.size() != 7) {
    throw std::invalid_argument(
        "--clip-box: expected six numbers XMIN,YMIN,ZMIN,XMAX,YMAX,ZMAX, "
        "and optionally a seventh, YAW, found " +
        std::to_string(items.size()) + " items in '" + std::string(text) + "'");
  }
  std::array<double, 7> values{};
  for (std::size_t i = 0; i < items.size(); ++i) {
    const std::string_view item = items[i];
    const char* begin = item.data();
    if (!item.empty() && item.front() == '+') ++begin;  // from_chars takes no plus sign
    const auto [end, error] = std::from_chars(begin, item.data() + item.size(), values[i]);
    if (item.empty() || error != std::errc{} || end != item.data() + item.size() ||
        !std::isfinite(values[i])) {
      throw std::invalid_argument(
          "--clip-box: " + std::string(kNames[i]) + " " + quotedItem(item) +
          (i == 6 ? " is not a number: expected degrees, counter-clockwise seen from above, "
                    "such as 30"
                  : " is not a number: expected a world coordinate such as 500123.25"));
    }
  }
  ClipBox clip;
  clip.yaw_degrees = values[6];
  for (int axis = 0; axis < 3; ++axis) {
    clip.box.min[std::size_t(axis)] = values[std::size_t(axis)];
    clip.box.max[std::size_t(axis)] = values[std::size_t(axis) + 3];
    if (clip.box.min[std::size_t(axis)] > clip.box.max[std::size_t(axis)]) {
      throw std::invalid_argument("--clip-box: " + std::string(kNames[std::size_t(axis)]) + " " +
                                  quotedItem(items[std::size_t(axis)]) + " is greater than " +
                                  kNames[std::size_t(axis) + 3] + " " +
                                  quotedItem(items[std::size_t(axis) + 3]) +
                                  ": expected each minimum at most its maximum");
    }
  }
  return clip;
}

ReturnSelection parseReturnList(std::string_view text) {
  ReturnSelection selection;
  for (const std::string_view item : splitItems(text)) {
    const auto kind = std::find_if(std::begin(kReturnKinds), std::end(kReturnKinds),
                                   [&](const auto& k) { return item == k.first; });
    if (kind != std::end(kReturnKinds)) {
      selection.kinds.push_back(kind->second);
      continue;
    }
    const std::size_t dash = item.find('-', 1);
    if (dash == std::string_view::npos) {
      const int r = returnNumber(item);
      if (r < 0) {
        throw std::invalid_argument("--returns: item " + quotedItem(item) +
                                    " is not a return: " + kReturnsExpected);
      }
      selection.numbers.push_back(r);
      continue;
    }
    const int first = returnNumber(item.substr(0, dash)),
              last = returnNumber(item.substr(dash + 1));
    if (first < 0 || last < 0 || first > last) {
      throw std::invalid_argument(
          "--returns: item " + quotedItem(item) +
          " is not a range N-M with 1 <= N <= M <= 15: " + kReturnsExpected);
    }
    for (int r = first; r <= last; ++r) selection.numbers.push_back(r);
  }
  return selection;
}

ValueRange parseRange(std::string_view name, std::string_view text) {
  const std::vector<std::string_view> items = splitItems(text);
  const std::string option(name);
  if (items.size() != 2) {
    throw std::invalid_argument(option + ": expected two numbers MIN,MAX, found " +
                                std::to_string(items.size()) + " items in '" + std::string(text) +
                                "'");
  }
  const std::optional<double> min = numberOf(items[0]), max = numberOf(items[1]);
  for (int i = 0; i < 2; ++i) {
    if (!(i == 0 ? min : max)) {
      throw std::invalid_argument(option + ": " + (i == 0 ? "MIN " : "MAX ") +
                                  quotedItem(items[std::size_t(i)]) +
                                  " is not a number: expected MIN,MAX such as 100,2000");
    }
  }
  if (*min > *max) {
    throw std::invalid_argument(option + ": MIN " + quotedItem(items[0]) + " is greater than MAX " +
                                quotedItem(items[1]) + ": expected MIN <= MAX");
  }
  return {*min, *max};
}

PointFilter pointFilterFrom(const FilterOptions& o, FilterTarget target) {
  PointFilter filter;
  if (!o.classes.empty()) filter.keepOnlyClasses(parseClassList(o.classes));
  if (!o.returns.empty()) {
    const ReturnSelection selection = parseReturnList(o.returns);
    filter.keepOnlyReturns(selection.kinds, selection.numbers);
  }
  if (!o.intensity.empty()) filter.intensity = parseRange("--intensity", o.intensity);
  if (!o.elevation.empty()) filter.elevation = parseRange("--elevation", o.elevation);
  if (!o.gps_time.empty()) filter.gps_time = parseRange("--gps-time", o.gps_time);
  if (!o.clip_mode.empty() && o.clip_mode != "inside" && o.clip_mode != "outside" &&
      o.clip_mode != "highlight") {
    throw std::invalid_argument("--clip-mode: unknown mode '" + o.clip_mode +
                                (target == FilterTarget::Gpu ? "' (use inside|outside|highlight)"
                                                             : "' (use inside|outside)"));
  }
  if (o.clip_mode == "highlight" && target == FilterTarget::Cpu) {
    throw std::invalid_argument(
        "--clip-mode: highlight tints the region in a picture and keeps every point: use it with "
        "render or view; here use inside or outside");
  }
  if (!o.clip_mode.empty() && o.clip_box.empty() && o.clip_polygon.empty()) {
    throw std::invalid_argument("--clip-mode: needs a region: give --clip-box or --clip-polygon");
  }
  const bool outside = o.clip_mode == "outside";
  filter.clip_highlight = o.clip_mode == "highlight";
  if (!o.clip_box.empty()) {
    const ClipBox clip = parseClipBox(o.clip_box);
    filter.setClipBox(clip.box, outside, clip.yaw_degrees);
  }
  if (!o.clip_polygon.empty()) {
    filter.polygon = readPolygonFile(o.clip_polygon);
    filter.clip_outside = outside;
    if (target == FilterTarget::Gpu &&
        filter.polygon.size() > PointFilter::kMaxGpuPolygonVertices) {
      throw std::invalid_argument(
          "--clip-polygon: " + o.clip_polygon + " has " + std::to_string(filter.polygon.size()) +
          " vertices; the shaders take at most " +
          std::to_string(PointFilter::kMaxGpuPolygonVertices) +
          " (simplify it, or cut the points with `parallax convert --clip-polygon`, which has no "
          "limit, and draw the result)");
    }
  }
  return filter;
}

}  // namespace parallax::cli
