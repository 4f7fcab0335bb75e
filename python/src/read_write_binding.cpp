// parallax.read, parallax.read_chunks and parallax.write: the format table (io/point_file.h)
// behind Python functions. The GIL is released for the I/O and the decoding.
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <algorithm>
#include <atomic>
#include <filesystem>
#include <memory>
#include <mutex>
#include <set>

#include "core/color_depth.h"
#include "core/progress.h"
#include "core/throttled_progress.h"
#include "io/coordinate_system.h"
#include "io/las_header.h"
#include "io/point_file.h"
#include "python_module.h"

namespace py = pybind11;

namespace parallax::python {

namespace {

bool isUrl(const std::string& path) {
  return path.rfind("http://", 0) == 0 || path.rfind("https://", 0) == 0;
}

CloudMetadata metadataOf(const std::filesystem::path& path, const CoordinateSystem* crs) {
  CloudMetadata metadata;
  metadata.path = path.string();
  const PointFormat format = detectPointFormat(path);
  metadata.format = std::string(format.id());
  const CoordinateSystem stated = crs ? *crs : readPointFileHeader(path).crs;
  metadata.crs_wkt = stated.description.wkt;
  metadata.crs_summary = stated.summary();
  // Read again here (the reader had it, but the format table keeps it to itself): for a URL one
  // more request, of the first kLasHeadBytes, which hold the header and nearly always every VLR.
  if (format == PointFormat::Las || format == PointFormat::Laz) {
    const LasHeader header = readLasHeaderWithRecords(path);
    metadata.las_point_format = header.point_format;
    metadata.las_version = header.versionString();
    metadata.vlrs = header.vlrs;
  }
  return metadata;
}

// Drops the columns not in `wanted` (x, y and z are always kept: positions are one column).
void keepOnlyColumns(PointCloud& cloud, const std::vector<std::string>& wanted) {
  const auto names = columnNames(cloud);
  for (const auto& name : wanted) {
    if (std::find(names.begin(), names.end(), name) == names.end()) {
      std::string list;
      for (const auto& n : names) list += (list.empty() ? "" : ", ") + n;
      throw py::key_error("columns: no column '" + name + "' in this file; its columns: " + list);
    }
  }
  const std::set<std::string> keep(wanted.begin(), wanted.end());
  const auto any = [&](std::initializer_list<const char*> group) {
    return std::any_of(group.begin(), group.end(), [&](const char* n) { return keep.count(n); });
  };
  if (!any({"red", "green", "blue", "alpha"})) {
    cloud.colors = {};
    cloud.stored_colors = {};
  }
  if (!any({"nx", "ny", "nz"})) cloud.normals = {};
  if (!keep.count("intensity")) cloud.intensity = {};
  if (!keep.count("classification")) cloud.classification = {};
  std::erase_if(cloud.scalars, [&](const ScalarColumn& c) { return !keep.count(c.name); });
}

// Colours written through pc["red"] (and green, blue) change the 8-bit display column; a LAS
// source's stored 16-bit values would be written back over them (core/point_cloud.h: code that
// changes `colors` must update `stored_colors`). Before a write, every point whose display colour
// is no longer that of its stored one gets a stored colour from it, by the reader's 8-bit rule
// (core/color_depth.h: in a file whose values are all below 256 they are kept as they are).
void storeChangedColours(PointCloud& cloud) {
  if (cloud.stored_colors.size() != cloud.count || cloud.colors.size() != cloud.count) return;
  const Rgb16* stored = cloud.stored_colors.data();
  const bool eight = std::all_of(stored, stored + cloud.count, [](const Rgb16& c) {
    return c.r < 256 && c.g < 256 && c.b < 256;
  });
  // Channel by channel: a 16-bit value whose display form is unchanged keeps every bit.
  const auto sync = [&](std::uint16_t& value, std::uint8_t display) {
    if (shownColor(value, eight) != display) value = storedColor(display, eight);
  };
  for (std::size_t i = 0; i < cloud.count; ++i) {
    const Rgba8 c = cloud.colors[i];
    Rgb16& s = cloud.stored_colors[i];
    sync(s.r, c.r);
    sync(s.g, c.g);
    sync(s.b, c.b);
  }
}

// A Progress that calls a Python callable with (done, total) from whichever thread advances it,
// as often as ThrottledProgress reports, with the GIL taken for each call. An exception the
// callable raises is kept and raised again by finish(), once the work is done (the readers
// cannot be interrupted mid-file).
class PythonProgress final : public ThrottledProgress {
 public:
  PythonProgress(py::object callback, std::uint64_t total)
      : ThrottledProgress(total), callback_(std::move(callback)) {}

  // The last call, (total, total) when the total was known; raises what the callable raised.
  // Needs the GIL.
  void finish() {
    report(std::max(done(), total()));
    if (error_) throw std::move(*error_);
  }

 private:
  void report(std::uint64_t done) override {
    if (error_) return;
    py::gil_scoped_acquire gil;
    try {
      callback_(done, total() ? py::object(py::int_(total())) : py::object(py::none()));
    } catch (py::error_already_set& error) {
      error_ = std::make_unique<py::error_already_set>(std::move(error));
    }
  }

  py::object callback_;
  std::unique_ptr<py::error_already_set> error_;
};

// What a read's progress counts to: points where the header states them, else bytes (text).
std::uint64_t progressTotal(const std::string& path) {
  if (detectPointFormat(path) == PointFormat::Text) {
    return isUrl(path) ? 0 : std::filesystem::file_size(path);
  }
  return headerPointCount(path).value_or(0);
}

CloudPtr read(const std::string& path, const std::optional<std::vector<std::string>>& columns,
              const std::vector<std::string>& text_columns, bool parallel,
              const FilterArguments& filter_arguments, const py::object& progress_callback) {
  const PointFilter filter = pointFilterFrom(filter_arguments);  // before any I/O
  auto handle = std::make_shared<CloudHandle>();
  std::unique_ptr<PythonProgress> progress;
  if (!progress_callback.is_none()) {
    py::gil_scoped_release release;
    const std::uint64_t total = progressTotal(path);
    py::gil_scoped_acquire gil;
    progress = std::make_unique<PythonProgress>(progress_callback, total);
  }
  {
    py::gil_scoped_release release;
    // Readers that can skip what was not asked for (LAZ of formats 6-10, COPC: layers never
    // decompressed) do; the others decode whole records, and keepOnlyColumns frees the rest.
    const AttributeSelection attributes =
        columns ? AttributeSelection::only(*columns) : AttributeSelection();
    handle->cloud = readPointFile(path, {.progress = progress.get(),
                                         .parallel = parallel,
                                         .text_columns = text_columns,
                                         .attributes = attributes});
    if (!filter.keepsAll()) handle->cloud = filterPoints(handle->cloud, filter);
    handle->metadata = metadataOf(path, nullptr);
  }
  if (progress) progress->finish();
  if (columns) keepOnlyColumns(handle->cloud, *columns);
  return handle;
}

// parallax.read_header: what the header says, without the points.
py::dict readHeader(const std::string& path) {
  PointFileHeader header;
  CloudMetadata metadata;
  {
    py::gil_scoped_release release;
    header = readPointFileHeader(path);
    metadata = metadataOf(path, &header.crs);
  }
  py::dict result;
  result["path"] = metadata.path;
  result["format"] = metadata.format;
  result["point_count"] =
      header.point_count ? py::object(py::int_(*header.point_count)) : py::none();
  result["bounds"] = py::none();
  if (header.bounds) {
    const auto& b = *header.bounds;
    result["bounds"] = py::make_tuple(py::make_tuple(b.min[0], b.min[1], b.min[2]),
                                      py::make_tuple(b.max[0], b.max[1], b.max[2]));
  }
  result["crs"] = metadata.crs_summary;
  result["crs_wkt"] = metadata.crs_wkt.empty() ? py::object(py::none()) : py::str(metadata.crs_wkt);
  result["point_format"] =
      metadata.las_point_format ? py::object(py::int_(*metadata.las_point_format)) : py::none();
  result["las_version"] =
      metadata.las_version.empty() ? py::object(py::none()) : py::str(metadata.las_version);
  result["vlrs"] = metadata.vlrs;
  return result;
}

// parallax.read_chunks: an iterator of PointClouds of at most `points` points each.
class ChunkReader {
 public:
  ChunkReader(const std::string& path, std::size_t points,
              const std::vector<std::string>& text_columns)
      : points_(points) {
    if (points == 0) throw py::value_error("points: expected a positive number of points a chunk");
    py::gil_scoped_release release;
    source_ = openPointChunks(path, {.text_columns = text_columns});
    metadata_ = metadataOf(path, &source_->crs());
  }

  CloudPtr next() {
    auto handle = std::make_shared<CloudHandle>();
    bool more = false;
    {
      py::gil_scoped_release release;
      more = source_->next(handle->cloud, points_);
    }
    if (!more) throw py::stop_iteration();
    handle->metadata = metadata_;
    return handle;
  }

  std::uint64_t pointCount() const { return source_->pointCount(); }
  const Quantization& quantization() const { return source_->quantization(); }

 private:
  std::unique_ptr<PointChunkSource> source_;
  CloudMetadata metadata_;
  std::size_t points_;
};

PcdData pcdDataOf(const std::string& name) {
  if (name == "binary") return PcdData::Binary;
  if (name == "ascii") return PcdData::Ascii;
  if (name == "binary_compressed") return PcdData::BinaryCompressed;
  throw py::value_error(
      "pcd_data: expected \"binary\", \"ascii\" or \"binary_compressed\", found '" + name + "'");
}

int lasMinorOf(const std::optional<std::string>& version) {
  if (!version) return 0;
  if (*version == "1.2") return 2;
  if (*version == "1.3") return 3;
  if (*version == "1.4") return 4;
  throw py::value_error("las_version: expected \"1.2\", \"1.3\" or \"1.4\", found '" + *version +
                        "'");
}

void write(const std::filesystem::path& path, const py::object& points, bool ascii,
           const std::optional<std::string>& las_version, int point_format,
           std::uint32_t laz_chunk_points, const std::string& pcd_data,
           const std::vector<std::string>& properties,
           const std::optional<std::array<double, 3>>& scale,
           const std::optional<std::array<double, 3>>& offset) {
  PointWriteOptions options{.ply_ascii = ascii,
                            .las_minor_version = lasMinorOf(las_version),
                            .las_point_format = point_format,
                            .laz_chunk_points = laz_chunk_points,
                            .pcd_data = pcdDataOf(pcd_data),
                            .properties = properties};
  // A cloud read from a file is written as it is (no copy), keeping a LAS source's header, VLRs
  // and records as `parallax convert` does; a dict of arrays becomes a cloud first.
  CloudPtr owner;
  PointCloud built;
  const PointCloud* cloud = nullptr;
  if (py::isinstance<CloudHandle>(points)) {
    owner = points.cast<CloudPtr>();
    cloud = &owner->cloud;
    options.source = owner->metadata.path;
    if (scale || offset) {
      throw py::value_error("scale, offset: only for a dict of arrays; a PointCloud keeps its own");
    }
  } else if (py::isinstance<py::dict>(points)) {
    built = cloudFromArrays(points.cast<py::dict>(), scale, offset);
    cloud = &built;
  } else {
    throw py::type_error("write: expected a parallax.PointCloud or a dict of numpy arrays, found " +
                         std::string(py::str(points.get_type())));
  }
  if (point_format < -1 || point_format > 10) {
    throw py::value_error("point_format: expected a LAS point format 0-10, found " +
                          std::to_string(point_format));
  }
  std::vector<std::string> losses;
  {
    py::gil_scoped_release release;
    if (owner) storeChangedColours(owner->cloud);
    losses = describeWriteLosses(*cloud, path, options);
    writePointFile(*cloud, path, options);
  }
  // What the output has no place for, as the command line reports it.
  for (const auto& loss : losses) {
    PyErr_WarnEx(PyExc_UserWarning, (path.string() + ": not kept: " + loss).c_str(), 1);
  }
}

}  // namespace

void bindReadWrite(py::module_& m) {
  m.def(
      "read",
      [](const std::string& path, const std::optional<std::vector<std::string>>& columns,
         const std::vector<std::string>& text_columns, bool parallel, const py::object& classes,
         const py::object& returns, const py::object& intensity, const py::object& elevation,
         const py::object& gps_time, const py::object& clip_box, const py::object& clip_polygon,
         const std::string& clip_mode, const py::object& progress) {
        return read(
            path, columns, text_columns, parallel,
            {classes, returns, intensity, elevation, gps_time, clip_box, clip_polygon, clip_mode},
            progress);
      },
      py::arg("path"), py::arg("columns") = py::none(), py::kw_only(),
      py::arg("text_columns") = std::vector<std::string>{}, py::arg("parallel") = true,
      py::arg("classes") = py::none(), py::arg("returns") = py::none(),
      py::arg("intensity") = py::none(), py::arg("elevation") = py::none(),
      py::arg("gps_time") = py::none(), py::arg("clip_box") = py::none(),
      py::arg("clip_polygon") = py::none(), py::arg("clip_mode") = "inside",
      py::arg("progress") = py::none(),
      R"doc(Reads a whole point file of any format Parallax reads (detected by content).

columns: the column names to keep (x, y, z always are); None keeps all.
text_columns: text files only, the columns' names ("x", "y", "z", "_" to skip one).
classes, returns, intensity, elevation, gps_time, clip_box, clip_polygon, clip_mode: the
command line's filters (classes=[2, 6], returns=["first"], intensity=(0, 200),
clip_box=(xmin, ymin, zmin, xmax, ymax, zmax), clip_polygon=[(x, y), ...]).
progress: a callable(done, total) called as the file is read, in points (bytes for text;
total None where unknown), last with done == total; e.g. a tqdm bar's update.
Raises parallax.InputError (a ValueError) for a malformed or unreadable file.)doc");

  m.def("read_header", &readHeader, py::arg("path"),
        "What a point file's header says, without reading its points: a dict of path, format, "
        "point_count (None where the format states none: text), bounds (the declared ones: LAS; "
        "else None), crs, crs_wkt, point_format, las_version, vlrs");

  py::class_<ChunkReader>(m, "ChunkReader", "An iterator of PointClouds read in chunks")
      .def("__iter__", [](ChunkReader& reader) -> ChunkReader& { return reader; })
      .def("__next__", &ChunkReader::next)
      .def_property_readonly("point_count", &ChunkReader::pointCount)
      .def_property_readonly("scale",
                             [](const ChunkReader& reader) {
                               const auto& s = reader.quantization().scale;
                               return py::make_tuple(s[0], s[1], s[2]);
                             })
      .def_property_readonly("offset", [](const ChunkReader& reader) {
        const auto& o = reader.quantization().offset;
        return py::make_tuple(o[0], o[1], o[2]);
      });
  m.def(
      "read_chunks",
      [](const std::string& path, std::size_t points,
         const std::vector<std::string>& text_columns) {
        return std::make_unique<ChunkReader>(path, points, text_columns);
      },
      py::arg("path"), py::kw_only(), py::arg("points") = 1'000'000,
      py::arg("text_columns") = std::vector<std::string>{},
      "The points of a file or URL of any size in PointClouds of at most `points` points, in file "
      "order (the format table's chunk source: memory stays bounded by the chunk; a URL's LAS or "
      "LAZ is read by range, other formats fetched whole)");

  m.def(
      "write", &write, py::arg("path"), py::arg("points"), py::kw_only(), py::arg("ascii") = false,
      py::arg("las_version") = py::none(), py::arg("point_format") = -1,
      py::arg("laz_chunk_points") = 50000, py::arg("pcd_data") = "binary",
      py::arg("properties") = std::vector<std::string>{}, py::arg("scale") = py::none(),
      py::arg("offset") = py::none(),
      R"doc(Writes a PointCloud, or a dict of numpy arrays (x, y, z in world coordinates required),
in the format of the path's extension (.ply .las .laz .xyz/.txt/.csv .pcd .e57 .ptx ...).

A PointCloud read from a LAS or LAZ file keeps its header fields, VLRs and point format, as
`parallax convert` does. ascii: PLY or PCD text. las_version ("1.2", "1.3", "1.4") and
point_format (0-10): LAS and LAZ. properties: PLY and text, the columns in this order.
scale, offset: a dict's position grid (default: the finest that holds its bounds).
The file appears under its name only when complete. Attributes the format has no place for are
reported with a UserWarning.)doc");
}

}  // namespace parallax::python
