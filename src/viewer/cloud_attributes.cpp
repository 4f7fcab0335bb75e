// A file the viewer draws whole is read with what its first picture needs, and the rest of its
// attributes when first asked for (issue 25 item 4). A LAZ of formats 6-10 keeps each field group
// in its own layer, so a format-7 file shown in RGB never decodes its GPS time, flags, scan
// angle, user data or point source layers unless a filter, colour mode, pick or profile needs
// them. Other readers fill every column anyway: nothing is then left to read later, and this
// costs one header read.
//
// The first read takes what the look asked on the command line draws (render_settings.h
// attributesDrawn), the colour (intensity where the file has none: what the default RGB look
// then shows), the classification (the filter panel lists the classes present) and the normals
// (the look lights a cloud that has them). A later attribute is read into the same cloud
// (lod/drawing_input.h readMissingAttributes): the positions stay, and the cloud is uploaded
// again so that the renderer sees the new columns. The read runs on the frame loop: a switch
// that needs a layer waits for its decode (0.2-0.7 s for 4 M points of format 7), once.
#include <algorithm>
#include <array>
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include "io/point_file.h"
#include "lod/drawing_input.h"
#include "render/render_settings.h"
#include "render/scalar_colors.h"
#include "viewer/joined_names.h"
#include "viewer/viewer_session.h"

namespace parallax::viewer_internal {
namespace {

// What a scalar colouring cannot take (scalar_colors.h: intensity and the scalar columns can).
constexpr std::array<const char*, 11> kNotScalarFields{column_names::kX,
                                                       column_names::kY,
                                                       column_names::kZ,
                                                       column_names::kRed,
                                                       column_names::kGreen,
                                                       column_names::kBlue,
                                                       column_names::kAlpha,
                                                       column_names::kNx,
                                                       column_names::kNy,
                                                       column_names::kNz,
                                                       column_names::kClassification};

bool fileHolds(const std::vector<std::string>& names, const char* name) {
  return std::find(names.begin(), names.end(), name) != names.end();
}

// Reads what `wanted` asks that the cloud lacks; on success uploads the cloud again and tells
// the panel and stderr (the tests read that line). False where nothing was read.
bool readIntoCloud(Session& s, const AttributeSelection& wanted) {
  if (s.cloud_file.empty() || !s.cloud_points) return false;
  std::vector<std::string> added;
  try {
    added = readMissingAttributes(s.cloud_file, s.cloud_file_attributes, wanted, *s.cloud_points);
  } catch (const std::exception& e) {
    s.status = "cannot read more of " + s.cloud_file.string() + ": " + e.what();
    s.error = s.status;
    s.cloud_file.clear();  // (not tried again every frame)
    std::fprintf(stderr, "parallax view: %s\n", s.status.c_str());
    return false;
  }
  // A name the header listed that the read did not give is not asked for again every frame.
  const std::vector<std::string> held = s.cloud_points->attributeNames();
  std::erase_if(s.cloud_file_attributes, [&](const std::string& name) {
    return wanted.wants(name) && std::find(held.begin(), held.end(), name) == held.end();
  });
  if (added.empty()) return false;
  uploadShownCloud(s);
  updateFilterRanges(s);
  std::fprintf(stderr, "parallax view: read later from %s: %s\n",
               s.cloud_file.filename().string().c_str(), joinedNames(added).c_str());
  return true;
}

}  // namespace

void openCloudFile(Session& s, const std::filesystem::path& path, bool first) {
  std::vector<std::string> attributes = readPointFileHeader(path).attributes;
  AttributeSelection first_read = attributesDrawn(s.options->settings);
  first_read.add(fileHolds(attributes, column_names::kRed) ? column_names::kRed
                                                           : column_names::kIntensity);
  first_read.add(column_names::kClassification);
  for (const char* axis : {column_names::kNx, column_names::kNy, column_names::kNz})
    first_read.add(axis);
  PointCloud cloud = readPointFile(path, {.attributes = first_read});
  const std::vector<std::string> read = cloud.attributeNames();
  std::vector<std::string> unread;
  for (const std::string& name : attributes) {
    if (std::find(read.begin(), read.end(), name) == read.end()) unread.push_back(name);
  }
  showCloud(s, std::move(cloud), true, true, first);
  if (unread.empty()) return;
  s.cloud_file = path;
  s.cloud_file_attributes = std::move(attributes);
  std::fprintf(stderr, "parallax view: %s read with %s; read when asked for: %s\n",
               path.filename().string().c_str(), joinedNames(read).c_str(),
               joinedNames(unread).c_str());
}

void updateCloudAttributes(Session& s) {
  if (s.cloud) readIntoCloud(s, attributesDrawn(s.settings));
}

void completeCloud(Session& s) {
  if (s.cloud) readIntoCloud(s, AttributeSelection{});
}

std::vector<std::string> cloudScalarFields(const Session& s) {
  if (!s.cloud_points) return {};
  if (s.cloud_file.empty()) return scalarFieldNames(*s.cloud_points);
  // The file's, read or not, in its order: choosing one reads it (updateCloudAttributes).
  std::vector<std::string> fields;
  for (const std::string& name : s.cloud_file_attributes) {
    const bool not_scalar = std::any_of(kNotScalarFields.begin(), kNotScalarFields.end(),
                                        [&](const char* n) { return name == n; });
    if (!not_scalar) fields.push_back(name);
  }
  return fields;
}

}  // namespace parallax::viewer_internal
