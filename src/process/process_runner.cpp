// runProcess (process_runner.h): tiling, the steps in order, and the final write.
#include "process/process_runner.h"

#include <unistd.h>

#include <algorithm>
#include <cassert>
#include <cctype>
#include <cstdio>
#include <cstring>
#include <memory>
#include <optional>
#include <stdexcept>

#include "core/error.h"
#include "core/point_gather.h"
#include "io/las_writer.h"
#include "io/laz_writer.h"
#include "io/partial_output.h"
#include "io/ply_writer.h"
#include "io/text_writer.h"
#include "lod/copc_converter.h"
#include "lod/potree_converter.h"
#include "lod/potree_reader.h"
#include "process/sensor_positions.h"
#include "process/tile_queries.h"
#include "process/tile_set.h"

namespace parallax {

namespace {

constexpr std::uint8_t kLowNoiseClass = 7;

void checkSteps(const ProcessOptions& options) {
  const OutputKind kind = outputKind(options.output);
  if (kind == OutputKind::kPotree) checkPotreeOutput(options.output);
  if (kind == OutputKind::kPointFile &&
      formatForExtension(options.output) == PointFormat::Unknown) {
    throw std::invalid_argument("process: cannot write " + options.output.string() +
                                ": the output is a point file (.ply, .las, .laz, .xyz, .txt, "
                                ".csv, .pts), a COPC file (.copc.laz) or a Potree directory (a "
                                "name ending in '/' or without extension)");
  }
  if (options.inputs.empty()) throw std::invalid_argument("process: no input");
  // A point file goes into an existing folder, as convert's and raster's do (an octree's folders
  // are made, as convert makes them). The work folder beside the output used to create the
  // missing ones silently.
  if (kind == OutputKind::kPointFile) requireOutputFolder(options.output, "-o");
}

// The hidden work folder, removed with everything in it however the run ends.
class WorkFolder {
 public:
  explicit WorkFolder(std::filesystem::path output) {
    if (!output.has_filename()) output = output.parent_path();  // "dir/": beside dir
    const std::filesystem::path parent =
        output.has_parent_path() ? output.parent_path() : std::filesystem::path(".");
    std::string name = ".";
    name += output.filename().string();
    name += ".process-";
    name += std::to_string(::getpid());
    path_ = parent / name;
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~WorkFolder() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  WorkFolder(const WorkFolder&) = delete;
  WorkFolder& operator=(const WorkFolder&) = delete;
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

// Reads one tile's records of `size` bytes in order, a block at a time.
class RecordReader {
 public:
  RecordReader(const std::filesystem::path& path, std::size_t size) : path_(path), size_(size) {
    file_ = std::fopen(path.c_str(), "rb");
    if (!file_) throw std::runtime_error("cannot open work file " + path.string());
  }
  ~RecordReader() {
    if (file_) std::fclose(file_);
  }
  RecordReader(const RecordReader&) = delete;
  RecordReader& operator=(const RecordReader&) = delete;
  const std::byte* next() {
    if (at_ == filled_) {
      buffer_.resize(size_ * 4096);
      filled_ = std::fread(buffer_.data(), size_, 4096, file_);
      at_ = 0;
      if (filled_ == 0) throw std::runtime_error("work file " + path_.string() + " ends early");
    }
    return buffer_.data() + size_ * at_++;
  }

 private:
  std::filesystem::path path_;
  std::size_t size_;
  std::FILE* file_ = nullptr;
  std::vector<std::byte> buffer_;
  std::size_t at_ = 0, filled_ = 0;
};

struct Added {
  bool normals = false, curvature = false, distance = false, mark = false;
  bool classes = false;  // a ground step's "class" records: nonzero replaces the input's class
  // The last normals step asked for --orient sensor: the normals are turned towards each
  // point's sensor as they are written.
  bool towards_sensor = false;
  // Columns of the steps' own (m3c2Scalars, heightAboveGroundScalar), each once: a step run
  // again rewrites its records and moves its column last.
  std::vector<StepScalar> scalars;
  void addScalars(const std::vector<StepScalar>& columns) {
    for (const StepScalar& column : columns) {
      std::erase_if(scalars, [&](const StepScalar& a) { return a.name == column.name; });
      scalars.push_back(column);
    }
  }
};

// Each input's sensor positions, found before any work so that a file without them fails
// first; empty unless a normals step orients towards the sensor.
std::vector<SensorPositions> findSensors(const ProcessOptions& options) {
  std::vector<SensorPositions> sensors;
  for (const ProcessStep& step : options.steps) {
    const auto* n = std::get_if<NormalsStep>(&step);
    if (!n || n->orientation != NormalOrientation::kSensor) continue;
    for (const ConvertInput& input : options.inputs) {
      PointStream stream(input.path, input.text_columns, nullptr, &input.filter);
      PointCloud first;
      stream.next(first, 1);
      sensors.push_back(
          SensorPositions::of(input.path, first, describeStep(step) + " --orient sensor"));
    }
    break;
  }
  return sensors;
}

// Normal i of `normals` (x y z triples) turned to face `sensor` from point i of `batch`.
void faceSensor(const PointCloud& batch, std::size_t i, const SensorPositions& sensor,
                float* normal) {
  const std::array<double, 3> s = sensor.at(batch, i);
  const double to[3] = {s[0] - batch.worldX(i), s[1] - batch.worldY(i), s[2] - batch.worldZ(i)};
  if (double(normal[0]) * to[0] + double(normal[1]) * to[1] + double(normal[2]) * to[2] < 0.0) {
    for (int a = 0; a < 3; ++a) normal[a] = -normal[a];
  }
}

ScalarColumn& scalarFor(PointCloud& cloud, const std::string& name) {
  for (ScalarColumn& s : cloud.scalars) {
    if (s.name == name) {
      s.type = ScalarType::Float32;
      s.data = ByteBuffer(cloud.count * sizeof(float));
      return s;
    }
  }
  cloud.scalars.push_back({name, ScalarType::Float32, ByteBuffer(cloud.count * sizeof(float))});
  return cloud.scalars.back();
}

// The steps' columns on `out` (gathered from `batch`): one value a point in each vector.
void addColumns(PointCloud& out, const PointCloud& batch, const Added& added,
                const std::vector<float>& n3, const std::vector<float>& c1,
                const std::vector<float>& d1, const std::vector<std::uint8_t>& m1,
                const std::vector<std::uint8_t>& k1, const std::vector<ByteBuffer>& scalars) {
  out.quantization = batch.quantization;
  out.source = batch.source;
  if (added.normals) {
    out.normals = Column<Float3>(out.count);
    std::memcpy(out.normals.data(), n3.data(), n3.size() * sizeof(float));
    out.source.normal = ScalarType::Float32;
  }
  if (added.curvature) {
    std::memcpy(scalarFor(out, "curvature").data.data(), c1.data(), c1.size() * sizeof(float));
  }
  if (added.distance) {
    std::memcpy(scalarFor(out, "distance").data.data(), d1.data(), d1.size() * sizeof(float));
  }
  for (std::size_t s = 0; s < added.scalars.size(); ++s) {
    ScalarColumn& column = scalarFor(out, added.scalars[s].name);
    column.type = added.scalars[s].type;
    column.data = ByteBuffer(out.count * scalarSize(column.type));
    std::memcpy(column.data.data(), scalars[s].data(), column.data.size());
  }
  if ((added.mark || added.classes) && !out.hasClassification()) {
    out.classification = Column<std::uint8_t>(out.count);
    std::memset(out.classification.data(), 0, out.count);
  }
  if (added.classes) {
    for (std::size_t i = 0; i < out.count; ++i) {
      if (k1[i]) out.classification[i] = k1[i];
    }
  }
  if (added.mark) {
    for (std::size_t i = 0; i < out.count; ++i) {
      if (m1[i]) out.classification[i] = kLowNoiseClass;
    }
  }
}

// A one-point cloud with the output's columns: the layout of a streamed PLY whose first batch
// may keep no point.
PointCloud outputLayout(const PointCloud& batch, const Added& added) {
  const std::uint64_t first = 0;
  PointCloud out = gatherPoints(batch, std::span<const std::uint64_t>(&first, 1));
  std::vector<ByteBuffer> scalars;
  for (const StepScalar& s : added.scalars) scalars.emplace_back(scalarSize(s.type));
  addColumns(out, batch, added, std::vector<float>(3, 0.0f), {0.0f}, {0.0f}, {0}, {0}, scalars);
  return out;
}

// The kept points of one input batch with the steps' attributes.
PointCloud outputBatch(const PointCloud& batch, const TileSet& tiles, const Added& added,
                       std::vector<std::unique_ptr<RecordReader>>& kept,
                       std::vector<std::unique_ptr<RecordReader>>& normals,
                       std::vector<std::unique_ptr<RecordReader>>& curvature,
                       std::vector<std::unique_ptr<RecordReader>>& distance,
                       std::vector<std::unique_ptr<RecordReader>>& mark,
                       std::vector<std::unique_ptr<RecordReader>>& classes,
                       std::vector<std::vector<std::unique_ptr<RecordReader>>>& scalar_readers,
                       const SensorPositions* sensor) {
  std::vector<std::uint64_t> take;
  std::vector<float> n3, c1, d1;
  std::vector<std::uint8_t> m1, k1;
  std::vector<std::vector<std::byte>> scalar_bytes(added.scalars.size());
  for (std::size_t i = 0; i < batch.count; ++i) {
    const std::size_t t = tiles.tileOf(batch.worldX(i));
    const bool keep = *kept[t]->next() != std::byte{0};
    const std::byte* n = added.normals ? normals[t]->next() : nullptr;
    const std::byte* c = added.curvature ? curvature[t]->next() : nullptr;
    const std::byte* d = added.distance ? distance[t]->next() : nullptr;
    const std::byte* m = added.mark ? mark[t]->next() : nullptr;
    const std::byte* k = added.classes ? classes[t]->next() : nullptr;
    for (std::size_t s = 0; s < added.scalars.size(); ++s) {
      const std::byte* v = scalar_readers[s][t]->next();
      if (keep) {
        scalar_bytes[s].insert(scalar_bytes[s].end(), v, v + scalarSize(added.scalars[s].type));
      }
    }
    if (!keep) continue;
    take.push_back(i);
    if (n) {
      float v[3];
      std::memcpy(v, n, sizeof v);
      if (sensor) faceSensor(batch, i, *sensor, v);
      n3.insert(n3.end(), v, v + 3);
    }
    if (c) c1.push_back(*reinterpret_cast<const float*>(c));
    if (d) d1.push_back(*reinterpret_cast<const float*>(d));
    if (m) m1.push_back(std::uint8_t(*m));
    if (k) k1.push_back(std::uint8_t(*k));
  }
  PointCloud out = gatherPoints(batch, std::span<const std::uint64_t>(take));
  std::vector<ByteBuffer> scalars;
  for (const std::vector<std::byte>& bytes : scalar_bytes) {
    ByteBuffer buffer(bytes.size());
    std::memcpy(buffer.data(), bytes.data(), bytes.size());
    scalars.push_back(std::move(buffer));
  }
  addColumns(out, batch, added, n3, c1, d1, m1, k1, scalars);
  out.computeBounds();
  return out;
}

// The batches of an output that is not streamed (PCD, PTX) joined into one cloud.
PointCloud joinBatches(std::vector<PointCloud>& batches) {
  PointCloud all;
  std::uint64_t total = 0;
  for (const PointCloud& b : batches) total += b.count;
  if (batches.empty()) return all;
  const PointCloud& first = batches.front();
  all.count = total;
  all.quantization = first.quantization;
  all.source = first.source;
  auto join = [&](auto member) {
    using ColumnT = std::remove_cvref_t<decltype(first.*member)>;
    if ((first.*member).empty()) return;
    ColumnT column(total);
    std::size_t at = 0;
    for (const PointCloud& b : batches) {
      std::memcpy(column.data() + at, (b.*member).data(), (b.*member).size() * sizeof(column[0]));
      at += (b.*member).size();
    }
    all.*member = std::move(column);
  };
  join(&PointCloud::positions);
  join(&PointCloud::colors);
  join(&PointCloud::stored_colors);
  join(&PointCloud::normals);
  join(&PointCloud::intensity);
  join(&PointCloud::classification);
  for (std::size_t s = 0; s < first.scalars.size(); ++s) {
    const std::size_t size = scalarSize(first.scalars[s].type);
    ScalarColumn column{first.scalars[s].name, first.scalars[s].type, ByteBuffer(total * size)};
    std::size_t at = 0;
    for (const PointCloud& b : batches) {
      std::memcpy(column.data.data() + at, b.scalars[s].data.data(), b.scalars[s].data.size());
      at += b.scalars[s].data.size();
    }
    all.scalars.push_back(std::move(column));
  }
  batches.clear();
  all.computeBounds();
  return all;
}

std::vector<std::string> attributeSignature(const PointCloud& cloud) {
  std::vector<std::string> names = cloud.attributeNames();
  return names;
}

}  // namespace

// The largest value of each scalar column and of the classification over the kept points, in
// a one-point cloud with the output's columns: what a LAS or LAZ output's point format is chosen
// from (las_writer.h: LasStreamWriter), as if the whole output were one cloud.
class ColumnMaxima {
 public:
  bool empty() const { return cloud_.count == 0; }
  const PointCloud& cloud() const { return cloud_; }
  PointCloud take() { return std::move(cloud_); }
  // The first batch's one-point layout (outputLayout), before the first add.
  void start(PointCloud layout) {
    cloud_ = std::move(layout);
    for (ScalarColumn& s : cloud_.scalars) s.setFromDouble(0, 0.0);
    if (cloud_.hasClassification()) cloud_.classification[0] = 0;
  }
  void add(const PointCloud& batch) {
    for (std::size_t c = 0; c < batch.scalars.size(); ++c) {
      const ScalarColumn& column = batch.scalars[c];
      double m = cloud_.scalars[c].valueAsDouble(0);
      for (std::size_t i = 0; i < batch.count; ++i) m = std::max(m, column.valueAsDouble(i));
      cloud_.scalars[c].setFromDouble(0, m);
    }
    if (batch.hasClassification()) {
      std::uint8_t& m = cloud_.classification[0];
      for (std::size_t i = 0; i < batch.count; ++i) m = std::max(m, batch.classification[i]);
    }
  }

 private:
  PointCloud cloud_;
};

// What the last pass needs besides the options.
struct WritePass {
  const ProcessOptions& options;
  const TileSet& tiles;
  const Added& added;
  const std::vector<SensorPositions>& sensors;
  std::filesystem::path output;  // a point file: the output's, or the octree's temporary LAS
};

// The last pass: the inputs once more, in order, each point matched with its tile's next records
// and written as it comes (PLY, LAS, LAZ, text; the other formats held whole). A LAS
// or LAZ output's point format is chosen before its first record, from `las_layout` (a
// ColumnMaxima cloud) or, without one, from the first batch; returns the maxima of every kept
// point when they ask for another layout than the one written (a class above 31 first seen after
// the first batch), to write again with: once, as the maxima are then known.
std::optional<PointCloud> writeOutput(const WritePass& pass, ProcessReport& report,
                                      const PointCloud* las_layout) {
  const ProcessOptions& options = pass.options;
  const std::filesystem::path& output = pass.output;
  const TileSet& tiles = pass.tiles;
  const Added& added = pass.added;
  auto open = [&](bool wanted, const std::string& what, std::size_t size) {
    std::vector<std::unique_ptr<RecordReader>> readers(tiles.tiles());
    if (!wanted) return readers;
    for (std::size_t t = 0; t < tiles.tiles(); ++t) {
      if (!tiles.has(t, what) && tiles.count(t) > 0) {
        // A step that wrote these records for some tiles writes them for all; absent: zeros.
        const std::vector<std::byte> zeros(tiles.count(t) * size, std::byte{0});
        tiles.writeRecords<std::byte>(t, what, zeros);
      }
      if (tiles.count(t) > 0)
        readers[t] = std::make_unique<RecordReader>(tiles.file(t, what), size);
    }
    return readers;
  };
  auto kept = open(true, "kept", 1);
  auto normals = open(added.normals, "normals", 12);
  auto curvature = open(added.curvature, "curvature", 4);
  auto distance = open(added.distance, "distance", 4);
  auto mark = open(added.mark, "mark", 1);
  auto classes = open(added.classes, "class", 1);
  std::vector<std::vector<std::unique_ptr<RecordReader>>> scalar_readers;
  for (const StepScalar& s : added.scalars) {
    scalar_readers.push_back(open(true, s.name, scalarSize(s.type)));
  }

  auto bar = options.progress ? options.progress("writing", report.input_points) : nullptr;
  const PointFormat format = formatForExtension(output);
  const bool las_output = format == PointFormat::Las || format == PointFormat::Laz;
  const bool text_output = format == PointFormat::Text || format == PointFormat("pts");
  std::unique_ptr<PlyStreamWriter> ply;
  std::unique_ptr<TextStreamWriter> text;
  std::unique_ptr<LasStreamWriter> las_writer;
  ColumnMaxima maxima;
  std::vector<PointCloud> held;  // formats written whole
  std::vector<std::string> signature;
  Quantization quantization;
  LasWriteOptions las;
  if (format == PointFormat::Laz) las.laz_chunk_points = kDefaultLazChunkPoints;
  bool first = true;
  for (std::size_t input_index = 0; input_index < options.inputs.size(); ++input_index) {
    const ConvertInput& input = options.inputs[input_index];
    const SensorPositions* sensor =
        added.towards_sensor && added.normals ? &pass.sensors[input_index] : nullptr;
    PointStream stream(input.path, input.text_columns, nullptr, &input.filter);
    if (first && !stream.crs().empty()) las.vlrs = stream.crs().records;
    PointCloud batch;
    while (stream.next(batch, tiles.batchPoints())) {
      PointCloud out = outputBatch(batch, tiles, added, kept, normals, curvature, distance, mark,
                                   classes, scalar_readers, sensor);
      if (bar) bar->advance(batch.count);
      const PointCloud layout = outputLayout(batch, added);
      if (first) {
        signature = attributeSignature(layout);
        quantization = out.quantization;
        report.losses = describeWriteLosses(layout, output, options.write);
        if (format == PointFormat::Ply) {
          PlyWriteOptions ply_options{
              .format = options.write.ply_ascii ? PlyFormat::Ascii : PlyFormat::BinaryLittleEndian,
              .properties = options.write.properties};
          ply =
              std::make_unique<PlyStreamWriter>(output, layout, report.output_points, ply_options);
        } else if (text_output) {
          TextWriteOptions text_options = textOptionsForPath(output);
          text_options.properties = options.write.properties;
          text = std::make_unique<TextStreamWriter>(output, layout, report.output_points,
                                                    text_options);
        }
        first = false;
      } else if (attributeSignature(layout) != signature || !(out.quantization == quantization)) {
        throw InputError({.file = input.path.string(),
                          .expected = "the attributes and quantization of " +
                                      options.inputs.front().path.string() +
                                      " (the inputs of one process run are one cloud)",
                          .found = "other attributes or another scale and offset",
                          .hint = "convert the inputs into one file first"});
      }
      if (las_output) {
        if (maxima.empty()) maxima.start(outputLayout(batch, added));
        maxima.add(out);
        if (!las_writer) {
          // The first batch's maxima stand for the whole's unless the caller knows them.
          las_writer = std::make_unique<LasStreamWriter>(
              output, las_layout ? *las_layout : maxima.cloud(), report.output_points, las);
        }
      }
      if (out.count == 0) continue;
      if (ply) {
        ply->write(out);
      } else if (text) {
        text->write(out);
      } else if (las_writer) {
        las_writer->write(out);
      } else {
        held.push_back(std::move(out));
      }
    }
  }
  if (first)
    throw InputError(
        {.file = options.inputs.front().path.string(), .expected = "points", .found = "none"});
  if (ply) {
    ply->finish();
  } else if (text) {
    text->finish();
  } else if (las_writer) {
    const LasWritePlan whole = planLasWrite(maxima.cloud(), las, report.output_points);
    if (whole.point_format != las_writer->plan().point_format ||
        whole.minor_version != las_writer->plan().minor_version) {
      assert(!las_layout && "a layout from every point's maxima is the whole's");
      return maxima.take();  // the writer, unfinished, removes its temporary file
    }
    las_writer->finish();
  } else {
    writePointFile(joinBatches(held), output, options.write);
  }
  return std::nullopt;
}

// A stage's progress sink that first checks the run's cancel flag: every step reports its
// tiles, the spill and the write their batches, so this is the check per tile, in one place.
class CancellableProgress final : public Progress {
 public:
  CancellableProgress(std::unique_ptr<Progress> inner, const std::atomic<bool>& cancel)
      : inner_(std::move(inner)), cancel_(cancel) {}
  void advance(std::uint64_t amount) override {
    if (cancel_.load(std::memory_order_relaxed)) throw ProcessCancelled();
    if (inner_) inner_->advance(amount);
  }

 private:
  std::unique_ptr<Progress> inner_;
  const std::atomic<bool>& cancel_;
};

ProcessReport runProcess(const ProcessOptions& given) {
  ProcessOptions options = given;
  if (given.cancel) {
    options.progress = [&given](const std::string& stage, std::uint64_t total) {
      return std::unique_ptr<Progress>(std::make_unique<CancellableProgress>(
          given.progress ? given.progress(stage, total) : nullptr, *given.cancel));
    };
  }
  auto check = [&] {
    if (given.cancel && given.cancel->load()) throw ProcessCancelled();
  };
  checkSteps(options);
  const std::vector<SensorPositions> sensors = findSensors(options);
  const WorkFolder work(options.output);
  ProcessReport report;
  const std::uint64_t max_tile_points = std::max<std::uint64_t>(
      1024, options.memory_mb * (std::uint64_t(1) << 20) / kProcessBytesPerPoint);
  const TileSet tiles = TileSet::spill(options.inputs, work.path(), "tile", max_tile_points,
                                       nullptr, options.progress);
  report.input_points = tiles.points();
  report.tiles = tiles.tiles();
  traceMemory("spill", tiles.points());

  Added added;
  for (const ProcessStep& step : options.steps) {
    check();
    const StepContext context{tiles,
                              work.path(),
                              max_tile_points,
                              options.progress,
                              describeStep(step),
                              options.memory_mb,
                              &options.inputs};
    if (const auto* n = std::get_if<NormalsStep>(&step)) {
      runNormalsStep(*n, context);
      added.normals = true;
      added.curvature = added.curvature || n->curvature;
      added.towards_sensor = n->orientation == NormalOrientation::kSensor;
    } else if (const auto* o = std::get_if<OutliersStep>(&step)) {
      runOutliersStep(*o, context);
      added.mark = added.mark || o->mark;
    } else if (const auto* s = std::get_if<SubsampleStep>(&step)) {
      runSubsampleStep(*s, context);
    } else if (const auto* h = std::get_if<HeightAboveGroundStep>(&step)) {
      runHeightAboveGroundStep(*h, context);
      added.addScalars({heightAboveGroundScalar()});
    } else if (const auto* g = std::get_if<GroundStep>(&step)) {
      runGroundStep(*g, context);
      added.classes = true;
    } else if (const auto* m = std::get_if<M3c2Step>(&step)) {
      runM3c2Step(*m, context);
      added.addScalars(m3c2Scalars());
    } else {
      runDistanceStep(std::get<DistanceStep>(step), context);
      added.distance = true;
    }
    traceMemory("step " + context.label + " end");
  }
  report.later_rounds = tiles.statistics();

  // The write: the inputs once more, in order (twice for a LAS or LAZ output whose point
  // format the first batch did not foresee). An octree is built from a point file of the
  // result in the work folder, read by the builder as any input: LAS when every input is LAS or
  // LAZ (their CRS and the positions' scale and offset carried exactly, what the steps added as
  // extra bytes, normals as NormalX NormalY NormalZ, which the LAS reader gives back as normals),
  // PLY otherwise (a LAS file would add LAS's fixed fields, zeros, to a cloud that never had
  // them).
  check();
  report.output_points = tiles.keptPoints();
  const OutputKind kind = outputKind(options.output);
  const bool las_inputs =
      std::all_of(options.inputs.begin(), options.inputs.end(), [](const ConvertInput& input) {
        // An octree, local or at a URL (whose "directory" no file test sees), is no LAS file.
        if (isPotreeDirectory(input.path)) return false;
        const PointFormat format = detectPointFormat(input.path);
        return format == PointFormat::Las || format == PointFormat::Laz;
      });
  const WritePass pass{options, tiles, added, sensors,
                       kind == OutputKind::kPointFile
                           ? options.output
                           : work.path() / (las_inputs ? "processed.las" : "processed.ply")};
  if (const std::optional<PointCloud> maxima = writeOutput(pass, report, nullptr)) {
    writeOutput(pass, report, &*maxima);
  }
  traceMemory("write", report.output_points);
  if (kind == OutputKind::kPointFile) return report;
  check();
  report.losses.clear();  // those of the temporary LAS; an octree keeps every attribute
  PotreeConvertOptions build;
  build.build.memory_bytes = options.memory_mb << 20;
  // Not the cancellable sinks: the builders report from their own threads and pipelines, which
  // are not made to be left by an exception. They check the same flag themselves, once a batch,
  // a chunk or a node (lod/octree_build_options.h), and leave nothing behind.
  build.progress = given.progress;
  build.build.cancel = given.cancel;
  const std::vector<ConvertInput> processed = {ConvertInput{.path = pass.output}};
  try {
    if (kind == OutputKind::kPotree) {
      convertToPotree(processed, options.output, build);
    } else {
      convertToCopc(processed, options.output, {.potree = build});
    }
  } catch (const OctreeBuildCancelled&) {
    throw ProcessCancelled();
  }
  return report;
}

}  // namespace parallax
