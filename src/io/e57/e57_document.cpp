#include "io/e57/e57_document.h"

#include <libxml/parser.h>
#include <libxml/tree.h>

#include <bit>
#include <charconv>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>

#include "core/error.h"
#include "fast_float/fast_float.h"

namespace parallax {
namespace {

// The XML section as a tree of libxml2 nodes, with the path of each node kept for messages.
struct Context {
  const std::string& file;
  std::uint64_t xml_offset;
};

struct Element {
  const xmlNode* node = nullptr;
  std::string path;
};

std::string_view localName(const xmlNode* node) {
  return reinterpret_cast<const char*>(node->name);
}

[[noreturn]] void fail(const Context& context, const Element& at, const std::string& property,
                       const std::string& expected, const std::string& found) {
  throw InputError(
      {.file = context.file,
       .byte_offset = context.xml_offset,
       .line = at.node ? std::optional<std::uint64_t>(xmlGetLineNo(at.node)) : std::nullopt,
       .element = "XML " + at.path,
       .property = property,
       .expected = expected,
       .found = found});
}

std::optional<Element> child(const Element& parent, std::string_view name) {
  for (const xmlNode* c = parent.node->children; c; c = c->next) {
    if (c->type == XML_ELEMENT_NODE && localName(c) == name) {
      return Element{c, parent.path + "/" + std::string(name)};
    }
  }
  return std::nullopt;
}

Element requireChild(const Context& context, const Element& parent, std::string_view name) {
  auto found = child(parent, name);
  if (!found) fail(context, parent, std::string(name), "this child element", "none");
  return *found;
}

std::vector<Element> elementChildren(const Element& parent) {
  std::vector<Element> children;
  for (const xmlNode* c = parent.node->children; c; c = c->next) {
    if (c->type != XML_ELEMENT_NODE) continue;
    const std::string index = std::to_string(children.size());
    children.push_back({c, parent.path + "/" + index});
  }
  return children;
}

std::optional<std::string> attribute(const Element& element, const char* name) {
  xmlChar* value = xmlGetProp(element.node, reinterpret_cast<const xmlChar*>(name));
  if (!value) return std::nullopt;
  std::string text(reinterpret_cast<const char*>(value));
  xmlFree(value);
  return text;
}

std::string elementText(const Element& element) {
  xmlChar* value = xmlNodeGetContent(element.node);
  if (!value) return {};
  std::string content(reinterpret_cast<const char*>(value));
  xmlFree(value);
  return content;
}

std::string_view trim(std::string_view s) {
  while (!s.empty() && std::strchr(" \t\r\n", s.front())) s.remove_prefix(1);
  while (!s.empty() && std::strchr(" \t\r\n", s.back())) s.remove_suffix(1);
  return s;
}

std::int64_t parseInteger(const Context& context, const Element& at, const std::string& what,
                          std::string_view value) {
  value = trim(value);
  std::int64_t result = 0;
  const char* end = value.data() + value.size();
  const auto [ptr, ec] =
      std::from_chars(value.data() + (value.starts_with('+') ? 1 : 0), end, result);
  if (ec != std::errc() || ptr != end || value.empty()) {
    fail(context, at, what, "an integer", quoteInput(value));
  }
  return result;
}

double parseDouble(const Context& context, const Element& at, const std::string& what,
                   std::string_view value) {
  value = trim(value);
  if (value.starts_with('+')) value.remove_prefix(1);
  double result = 0;
  const char* end = value.data() + value.size();
  const auto [ptr, ec] = fast_float::from_chars(value.data(), end, result);
  if (ec != std::errc() || ptr != end || value.empty()) {
    fail(context, at, what, "a number", quoteInput(value));
  }
  return result;
}

std::string typeOf(const Element& element) {
  return attribute(element, "type").value_or("");
}

std::int64_t integerAttribute(const Context& context, const Element& element, const char* name,
                              std::int64_t fallback) {
  const auto value = attribute(element, name);
  return value ? parseInteger(context, element, name, *value) : fallback;
}

double doubleAttribute(const Context& context, const Element& element, const char* name,
                       double fallback) {
  const auto value = attribute(element, name);
  return value ? parseDouble(context, element, name, *value) : fallback;
}

// The value of an Integer, ScaledInteger or Float element (E2807 9.3-9.5: an empty element is 0).
double numberValue(const Context& context, const Element& element) {
  const std::string type = typeOf(element);
  const std::string content = elementText(element);
  const bool empty = trim(content).empty();
  if (type == "Integer") {
    return empty ? 0.0 : double(parseInteger(context, element, "value", content));
  }
  if (type == "ScaledInteger") {
    const double raw = empty ? 0.0 : double(parseInteger(context, element, "value", content));
    return raw * doubleAttribute(context, element, "scale", 1.0) +
           doubleAttribute(context, element, "offset", 0.0);
  }
  if (type == "Float") return empty ? 0.0 : parseDouble(context, element, "value", content);
  fail(context, element, "type", "Integer, ScaledInteger or Float", quoteInput(type));
}

std::optional<double> optionalNumber(const Context& context, const Element& parent,
                                     std::string_view name) {
  const auto element = child(parent, name);
  if (!element) return std::nullopt;
  return numberValue(context, *element);
}

unsigned bitsForRange(std::int64_t minimum, std::int64_t maximum) {
  const std::uint64_t span = std::uint64_t(maximum) - std::uint64_t(minimum);
  return unsigned(std::bit_width(span));
}

E57Field parseField(const Context& context, const Element& element) {
  E57Field field;
  field.name = std::string(localName(element.node));
  const std::string type = typeOf(element);
  constexpr auto kLowest = std::numeric_limits<std::int64_t>::min();
  constexpr auto kHighest = std::numeric_limits<std::int64_t>::max();
  if (type == "Integer" || type == "ScaledInteger") {
    field.kind = type == "Integer" ? E57Field::Kind::Integer : E57Field::Kind::ScaledInteger;
    field.minimum = integerAttribute(context, element, "minimum", kLowest);
    field.maximum = integerAttribute(context, element, "maximum", kHighest);
    if (field.minimum > field.maximum) {
      fail(context, element, "minimum, maximum", "minimum <= maximum",
           std::to_string(field.minimum) + " > " + std::to_string(field.maximum));
    }
    field.bits = bitsForRange(field.minimum, field.maximum);
    if (field.kind == E57Field::Kind::ScaledInteger) {
      field.scale = doubleAttribute(context, element, "scale", 1.0);
      field.offset = doubleAttribute(context, element, "offset", 0.0);
      if (!(field.scale != 0.0) || !std::isfinite(field.scale) || !std::isfinite(field.offset)) {
        fail(context, element, "scale", "a finite, non-zero scale and a finite offset",
             std::to_string(field.scale) + ", " + std::to_string(field.offset));
      }
    }
  } else if (type == "Float") {
    field.kind = E57Field::Kind::Float;
    const std::string precision = attribute(element, "precision").value_or("double");
    if (precision != "single" && precision != "double") {
      fail(context, element, "precision", "single or double", quoteInput(precision));
    }
    field.single_precision = precision == "single";
    field.bits = field.single_precision ? 32 : 64;
    const double limit = field.single_precision ? double(std::numeric_limits<float>::max())
                                                : std::numeric_limits<double>::max();
    field.float_minimum = doubleAttribute(context, element, "minimum", -limit);
    field.float_maximum = doubleAttribute(context, element, "maximum", limit);
  } else if (type == "String") {
    field.kind = E57Field::Kind::String;
  } else {
    fail(context, element, "type", "Integer, ScaledInteger, Float or String", quoteInput(type));
  }
  return field;
}

std::optional<std::array<double, 2>> parseLimitPair(const Context& context, const Element& scan,
                                                    const char* group, const char* low,
                                                    const char* high) {
  const auto limits = child(scan, group);
  if (!limits) return std::nullopt;
  const auto lo = optionalNumber(context, *limits, low);
  const auto hi = optionalNumber(context, *limits, high);
  // Writers leave both at 0 when they have nothing to say (CloudCompare does for intensity):
  // limits that span nothing are no limits.
  if (!lo || !hi || !(*lo < *hi) || !std::isfinite(*hi - *lo)) return std::nullopt;
  return std::array<double, 2>{*lo, *hi};
}

E57Pose parsePose(const Context& context, const Element& scan) {
  E57Pose pose;
  const auto element = child(scan, "pose");
  if (!element) return pose;
  if (const auto rotation = child(*element, "rotation")) {
    const char* names[4] = {"w", "x", "y", "z"};
    for (int i = 0; i < 4; ++i) {
      pose.rotation[i] = numberValue(context, requireChild(context, *rotation, names[i]));
    }
    const double norm =
        std::sqrt(pose.rotation[0] * pose.rotation[0] + pose.rotation[1] * pose.rotation[1] +
                  pose.rotation[2] * pose.rotation[2] + pose.rotation[3] * pose.rotation[3]);
    if (!(norm > 0.5 && norm < 2.0)) {
      fail(context, *rotation, "w, x, y, z", "a unit quaternion", "norm " + std::to_string(norm));
    }
  }
  if (const auto translation = child(*element, "translation")) {
    const char* names[3] = {"x", "y", "z"};
    for (int i = 0; i < 3; ++i) {
      pose.translation[i] = numberValue(context, requireChild(context, *translation, names[i]));
      if (!std::isfinite(pose.translation[i])) {
        fail(context, *translation, names[i], "a finite number", "not finite");
      }
    }
  }
  return pose;
}

E57Scan parseScan(const Context& context, const Element& scan_element) {
  E57Scan scan;
  if (const auto name = child(scan_element, "name")) scan.name = elementText(*name);
  if (const auto guid = child(scan_element, "guid")) scan.guid = elementText(*guid);
  const Element points = requireChild(context, scan_element, "points");
  if (typeOf(points) != "CompressedVector") {
    fail(context, points, "type", "CompressedVector", quoteInput(typeOf(points)));
  }
  const auto file_offset = attribute(points, "fileOffset");
  const auto record_count = attribute(points, "recordCount");
  if (!file_offset) fail(context, points, "fileOffset", "an attribute", "none");
  if (!record_count) fail(context, points, "recordCount", "an attribute", "none");
  const std::int64_t offset = parseInteger(context, points, "fileOffset", *file_offset);
  const std::int64_t count = parseInteger(context, points, "recordCount", *record_count);
  if (offset < 0) fail(context, points, "fileOffset", "a positive offset", *file_offset);
  if (count < 0) fail(context, points, "recordCount", "a count >= 0", *record_count);
  scan.section_offset = std::uint64_t(offset);
  scan.record_count = std::uint64_t(count);
  const Element prototype = requireChild(context, points, "prototype");
  for (const Element& field : elementChildren(prototype)) {
    Element named{field.node, prototype.path + "/" + std::string(localName(field.node))};
    scan.fields.push_back(parseField(context, named));
  }
  const bool cartesian =
      scan.field("cartesianX") || scan.field("cartesianY") || scan.field("cartesianZ");
  const char* required_cartesian[] = {"cartesianX", "cartesianY", "cartesianZ"};
  const char* required_spherical[] = {"sphericalRange", "sphericalAzimuth", "sphericalElevation"};
  for (const char* name : cartesian ? required_cartesian : required_spherical) {
    if (!scan.field(name)) {
      fail(context, prototype, name,
           "a field of the point record (cartesianX, Y, Z or sphericalRange, Azimuth, Elevation)",
           "none");
    }
  }
  for (const E57Field& field : scan.fields) {
    const bool needed = field.name.starts_with("cartesian") || field.name.starts_with("spherical");
    if (field.kind == E57Field::Kind::String && needed) {
      fail(context, prototype, field.name, "a number field", "a String");
    }
  }
  scan.pose = parsePose(context, scan_element);
  if (const auto bounds = child(scan_element, "cartesianBounds")) {
    const char* names[6] = {"xMinimum", "xMaximum", "yMinimum", "yMaximum", "zMinimum", "zMaximum"};
    std::array<std::optional<double>, 6> values;
    for (int i = 0; i < 6; ++i) values[i] = optionalNumber(context, *bounds, names[i]);
    bool complete = true;
    for (const auto& v : values) complete = complete && v && std::isfinite(*v);
    if (complete && *values[0] <= *values[1] && *values[2] <= *values[3] &&
        *values[4] <= *values[5]) {
      Bounds3 b;
      b.extend(*values[0], *values[2], *values[4]);
      b.extend(*values[1], *values[3], *values[5]);
      scan.cartesian_bounds = b;
    }
  }
  if (const auto bounds = child(scan_element, "sphericalBounds")) {
    const auto range = optionalNumber(context, *bounds, "rangeMaximum");
    if (range && std::isfinite(*range) && *range >= 0) scan.range_maximum = range;
  }
  scan.intensity_limits = parseLimitPair(context, scan_element, "intensityLimits",
                                         "intensityMinimum", "intensityMaximum");
  const auto red =
      parseLimitPair(context, scan_element, "colorLimits", "colorRedMinimum", "colorRedMaximum");
  const auto green = parseLimitPair(context, scan_element, "colorLimits", "colorGreenMinimum",
                                    "colorGreenMaximum");
  const auto blue =
      parseLimitPair(context, scan_element, "colorLimits", "colorBlueMinimum", "colorBlueMaximum");
  if (red && green && blue) {
    scan.color_limits = {(*red)[0], (*red)[1], (*green)[0], (*green)[1], (*blue)[0], (*blue)[1]};
  }
  return scan;
}

void parseImages(const Context& context, const Element& images, std::vector<E57Image>& out) {
  const char* representations[] = {"pinholeRepresentation", "sphericalRepresentation",
                                   "cylindricalRepresentation", "visualReferenceRepresentation"};
  for (const Element& image_element : elementChildren(images)) {
    E57Image image;
    if (const auto name = child(image_element, "name")) image.name = elementText(*name);
    for (const char* representation : representations) {
      const auto r = child(image_element, representation);
      if (!r) continue;
      image.representation = std::string(representation);
      image.representation.resize(image.representation.size() - std::strlen("Representation"));
      for (const auto& [blob_name, format] :
           {std::pair{"jpegImage", "JPEG"}, {"pngImage", "PNG"}}) {
        if (const auto blob = child(*r, blob_name)) {
          image.format = format;
          const std::int64_t length = integerAttribute(context, *blob, "length", 0);
          image.byte_length = length > 0 ? std::uint64_t(length) : 0;
        }
      }
      if (const auto width = child(*r, "imageWidth")) {
        image.width = parseInteger(context, *width, "value", elementText(*width));
      }
      if (const auto height = child(*r, "imageHeight")) {
        image.height = parseInteger(context, *height, "value", elementText(*height));
      }
      break;
    }
    out.push_back(std::move(image));
  }
}

struct DocDeleter {
  void operator()(xmlDoc* doc) const { xmlFreeDoc(doc); }
};
struct ContextDeleter {
  void operator()(xmlParserCtxt* context) const { xmlFreeParserCtxt(context); }
};

}  // namespace

double E57Field::lowest() const {
  switch (kind) {
    case Kind::Integer:
      return double(minimum);
    case Kind::ScaledInteger:
      return std::min(double(minimum) * scale + offset, double(maximum) * scale + offset);
    case Kind::Float:
      return float_minimum;
    case Kind::String:
      break;
  }
  return 0.0;
}

double E57Field::highest() const {
  switch (kind) {
    case Kind::Integer:
      return double(maximum);
    case Kind::ScaledInteger:
      return std::max(double(minimum) * scale + offset, double(maximum) * scale + offset);
    case Kind::Float:
      return float_maximum;
    case Kind::String:
      break;
  }
  return 0.0;
}

std::array<double, 9> E57Pose::matrix() const {
  double w = rotation[0], x = rotation[1], y = rotation[2], z = rotation[3];
  const double norm = std::sqrt(w * w + x * x + y * y + z * z);
  w /= norm, x /= norm, y /= norm, z /= norm;
  return {1 - 2 * (y * y + z * z), 2 * (x * y - w * z),     2 * (x * z + w * y),
          2 * (x * y + w * z),     1 - 2 * (x * x + z * z), 2 * (y * z - w * x),
          2 * (x * z - w * y),     2 * (y * z + w * x),     1 - 2 * (x * x + y * y)};
}

const E57Field* E57Scan::field(std::string_view field_name) const {
  for (const E57Field& f : fields) {
    if (f.name == field_name) return &f;
  }
  return nullptr;
}

E57Document parseE57Document(std::string_view xml, const std::string& file,
                             std::uint64_t xml_offset) {
  const Context context{file, xml_offset};
  std::unique_ptr<xmlParserCtxt, ContextDeleter> parser(xmlNewParserCtxt());
  if (!parser) throw std::bad_alloc();
  // No network, no entity substitution (an E57 file has no business with either), errors kept
  // in the parser rather than printed.
  const int options = XML_PARSE_NONET | XML_PARSE_NOERROR | XML_PARSE_NOWARNING;
  std::unique_ptr<xmlDoc, DocDeleter> doc(
      xmlCtxtReadMemory(parser.get(), xml.data(), int(xml.size()), nullptr, nullptr, options));
  if (!doc || !parser->wellFormed) {
    const xmlError* error = xmlCtxtGetLastError(parser.get());
    std::string message = error && error->message ? error->message : "unknown error";
    while (!message.empty() && message.back() == '\n') message.pop_back();
    throw InputError({.file = file,
                      .byte_offset = xml_offset,
                      .line = error ? std::optional<std::uint64_t>(error->line) : std::nullopt,
                      .element = "XML section",
                      .expected = "well-formed XML",
                      .found = message});
  }
  const Element root{xmlDocGetRootElement(doc.get()), ""};
  if (!root.node || localName(root.node) != "e57Root") {
    fail(context, {root.node, "/"}, "root element", "e57Root",
         root.node ? std::string(localName(root.node)) : "none");
  }
  E57Document document;
  if (const auto guid = child(root, "guid")) document.guid = elementText(*guid);
  if (const auto crs = child(root, "coordinateMetadata")) {
    document.coordinate_metadata = std::string(trim(elementText(*crs)));
  }
  const Element data3d = requireChild(context, root, "data3D");
  for (const Element& scan : elementChildren(data3d)) {
    document.scans.push_back(parseScan(context, scan));
  }
  if (const auto images = child(root, "images2D")) parseImages(context, *images, document.images);
  return document;
}

}  // namespace parallax
