// The table's mechanics: the built-in rows (point_formats.cpp) and those registered at run time,
// lookups by id, content and extension, and the lists that help texts and docs print.
#include "io/point_format.h"

#include <algorithm>
#include <cassert>
#include <cctype>
#include <deque>
#include <mutex>
#include <stdexcept>

#include "core/url.h"

namespace parallax {

// The built-in rows, in detection order (point_formats.cpp).
std::vector<PointFormatEntry> builtInPointFormats();

namespace {

struct Table {
  std::mutex mutex;
  std::deque<PointFormatEntry> rows;  // a deque: rows never move once listed
};

Table& table() {
  static Table* instance = [] {
    auto* t = new Table;  // never destroyed: rows outlive every static user
    for (PointFormatEntry& row : builtInPointFormats()) t->rows.push_back(std::move(row));
    return t;
  }();
  return *instance;
}

// A URL's query does not hide its extension (".../scan.pcd?token=..." names a PCD file).
std::string lowerExtension(const std::filesystem::path& path) {
  std::string ext = fileExtensionOf(path.string());
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return char(std::tolower(c)); });
  return ext;
}

// "PLY" from "PLY", "text" from "text (XYZ/CSV/PTS)".
std::string shortName(const PointFormatEntry& row) {
  return row.name.substr(0, row.name.find(' '));
}

// "a, b and c" ("or" for `last_word` "or").
std::string joinNames(const std::vector<std::string>& names, const char* last_word) {
  std::string out;
  for (std::size_t i = 0; i < names.size(); ++i) {
    if (i > 0) out += i + 1 == names.size() ? std::string(" ") + last_word + " " : ", ";
    out += names[i];
  }
  return out;
}

}  // namespace

const CoordinateSystem& PointChunkSource::crs() const {
  static const CoordinateSystem kNone;
  return kNone;
}

void PointChunkSource::skip(std::uint64_t) {
  assert(false && "PointChunkSource::skip: this format cannot skip (ask canSkip() first)");
}

const PointFormatEntry* PointFormat::entry() const {
  if (id_.empty()) return nullptr;
  Table& t = table();
  const std::lock_guard lock(t.mutex);
  for (const PointFormatEntry& row : t.rows) {
    if (row.id == id_) return &row;
  }
  return nullptr;
}

std::vector<const PointFormatEntry*> pointFormats() {
  Table& t = table();
  const std::lock_guard lock(t.mutex);
  std::vector<const PointFormatEntry*> out;
  for (const PointFormatEntry& row : t.rows) out.push_back(&row);
  return out;
}

PointFormat registerPointFormat(PointFormatEntry entry) {
  if (entry.id.empty() || entry.name.empty() || !entry.detect) {
    throw std::invalid_argument("registerPointFormat: a row needs an id, a name and a detect");
  }
  Table& t = table();
  const std::lock_guard lock(t.mutex);
  for (const PointFormatEntry& row : t.rows) {
    if (row.id == entry.id) {
      throw std::invalid_argument("registerPointFormat: '" + entry.id + "' is already listed");
    }
  }
  t.rows.push_back(std::move(entry));
  return PointFormat(t.rows.back().id);
}

PointFormat detectFormatOf(std::span<const std::byte> head) {
  const std::vector<const PointFormatEntry*> rows = pointFormats();
  for (const bool fallback : {false, true}) {
    for (const PointFormatEntry* row : rows) {
      if (row->fallback == fallback && row->detect(head)) return PointFormat(row->id);
    }
  }
  return PointFormat::Unknown;
}

PointFormat formatOfExtension(const std::filesystem::path& path) {
  const std::string ext = lowerExtension(path);
  if (ext.empty()) return PointFormat::Unknown;
  for (const PointFormatEntry* row : pointFormats()) {
    if (std::find(row->extensions.begin(), row->extensions.end(), ext) != row->extensions.end()) {
      return PointFormat(row->id);
    }
  }
  return PointFormat::Unknown;
}

std::string pointFormatNamesText() {
  std::vector<std::string> names;
  for (const PointFormatEntry* row : pointFormats()) names.push_back(shortName(*row));
  return joinNames(names, "or");
}

std::string previewFormatNamesText() {
  std::vector<std::string> names;
  for (const PointFormatEntry* row : pointFormats()) {
    if (row->preview) names.push_back(shortName(*row));
  }
  return joinNames(names, "and");
}

std::vector<std::string> writableExtensions() {
  std::vector<std::string> out;
  for (const PointFormatEntry* row : pointFormats()) {
    if (row->write) out.insert(out.end(), row->extensions.begin(), row->extensions.end());
  }
  return out;
}

std::string writableExtensionsText() {
  std::string out;
  for (const std::string& ext : writableExtensions()) out += (out.empty() ? "" : " ") + ext;
  return out;
}

std::string pointFormatsMarkdown() {
  std::string out =
      "| format | id | extensions | read | preview | stream | write | CRS "
      "written |\n| --- | --- | --- | --- | --- | --- | --- | --- |\n";
  for (const PointFormatEntry* row : pointFormats()) {
    std::string extensions;
    for (const std::string& ext : row->extensions) {
      extensions += (extensions.empty() ? "`" : " `") + ext + "`";
    }
    auto yes = [](bool b) { return b ? "yes" : "no"; };
    out += "| " + row->description + " | `" + row->id + "` | " + extensions + " | " +
           yes(bool(row->read)) + " | " + yes(bool(row->preview)) + " | " +
           yes(bool(row->open_chunks)) + " | " + yes(bool(row->write)) + " | " +
           yes(row->writes_crs) + " |\n";
  }
  return out;
}

}  // namespace parallax
