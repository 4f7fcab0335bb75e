// PointSpill (point_spill.h): batches in memory, then column bytes in a scratch file.
#include "lod/point_spill.h"

#include <fcntl.h>
#include <unistd.h>

#include <cassert>
#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <string>
#include <system_error>

#include "core/point_gather.h"

namespace parallax {
namespace {

[[noreturn]] void fail(const std::filesystem::path& file, const char* what) {
  throw std::system_error(errno, std::generic_category(),
                          file.string() + ": " + what + " (the conversion's scratch file)");
}

void writeAll(int fd, const std::filesystem::path& file, const std::byte* data, std::size_t size) {
  while (size > 0) {
    const ssize_t n = ::write(fd, data, size);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) fail(file, "cannot write");
    data += n;
    size -= std::size_t(n);
  }
}

void readAll(int fd, const std::filesystem::path& file, std::uint64_t offset, std::byte* data,
             std::size_t size) {
  while (size > 0) {
    const ssize_t n = ::pread(fd, data, size, off_t(offset));
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) fail(file, "cannot read");
    if (n == 0) {
      errno = EIO;
      fail(file, "ended early");
    }
    data += n;
    size -= std::size_t(n);
    offset += std::uint64_t(n);
  }
}

// Every column of a batch in one order, for writing and for reading back: the fields of
// PointCloud::clone(), less the shape the Batch keeps in memory.
template <class F>
void forEachColumn(PointCloud& cloud, F&& f) {
  f(reinterpret_cast<std::byte*>(cloud.positions.data()), cloud.positions.size() * sizeof(Int3));
  f(reinterpret_cast<std::byte*>(cloud.colors.data()), cloud.colors.size() * sizeof(Rgba8));
  f(reinterpret_cast<std::byte*>(cloud.stored_colors.data()),
    cloud.stored_colors.size() * sizeof(Rgb16));
  f(reinterpret_cast<std::byte*>(cloud.normals.data()), cloud.normals.size() * sizeof(Float3));
  f(reinterpret_cast<std::byte*>(cloud.intensity.data()), cloud.intensity.size() * sizeof(float));
  f(reinterpret_cast<std::byte*>(cloud.classification.data()), cloud.classification.size());
  for (ScalarColumn& column : cloud.scalars) f(column.data.data(), column.data.size());
}

// The batch's shape: its count, quantization, bounds, source types and the scalars' names and
// types, with no column bytes.
PointCloud shapeOf(const PointCloud& batch) {
  PointCloud shape;
  shape.count = batch.count;
  shape.quantization = batch.quantization;
  for (const ScalarColumn& column : batch.scalars)
    shape.scalars.push_back({column.name, column.type, {}});
  shape.source = batch.source;
  shape.bounds = batch.bounds;
  return shape;
}

}  // namespace

std::uint64_t pointCloudBytes(const PointCloud& cloud) {
  std::uint64_t bytes = 0;
  forEachColumn(const_cast<PointCloud&>(cloud),
                [&](const std::byte*, std::size_t size) { bytes += size; });
  return bytes;
}

// The kept batches handed out again, at most max_points at a time (a batch larger than that is
// handed out in slices).
class SpillReader final : public PointChunkSource {
 public:
  SpillReader(PointSpill& spill, bool last_pass, bool positions_only)
      : spill_(spill), last_pass_(last_pass), positions_only_(positions_only) {
    if (spill.fd_ >= 0) {
      fd_ = ::open(spill.file_.c_str(), O_RDONLY | O_CLOEXEC);
      if (fd_ < 0) fail(spill.file_, "cannot open");
    }
  }
  ~SpillReader() override {
    if (fd_ >= 0) ::close(fd_);
  }

  std::uint64_t pointCount() const override { return spill_.points_; }
  const Quantization& quantization() const override { return spill_.quantization_; }
  const CoordinateSystem& crs() const override { return spill_.crs_; }

  bool next(PointCloud& chunk, std::size_t max_points) override {
    while (next_point_ >= current_.count) {
      if (next_batch_ >= spill_.batches_.size()) {
        chunk = PointCloud{};
        return false;
      }
      current_ = load(spill_.batches_[next_batch_++]);
      next_point_ = 0;
    }
    const std::uint64_t n = std::min<std::uint64_t>(max_points, current_.count - next_point_);
    if (next_point_ == 0 && n == current_.count) {
      chunk = std::move(current_);
      current_ = PointCloud{};
    } else {
      chunk = slicePoints(current_, next_point_, n);
      chunk.computeBounds();
      next_point_ += n;
    }
    return true;
  }

 private:
  PointCloud load(PointSpill::Batch& entry) {
    if (positions_only_) return loadPositions(entry);
    if (!entry.in_file) {
      if (!last_pass_) return entry.cloud.clone();
      spill_.memory_used_ -= pointCloudBytes(entry.cloud);
      return std::move(entry.cloud);
    }
    PointCloud cloud = shapeOf(entry.cloud);
    const std::size_t n = std::size_t(cloud.count);
    cloud.positions = Column<Int3>(n);
    if (entry.has_colors) cloud.colors = Column<Rgba8>(n);
    if (entry.has_stored_colors) cloud.stored_colors = Column<Rgb16>(n);
    if (entry.has_normals) cloud.normals = Column<Float3>(n);
    if (entry.has_intensity) cloud.intensity = Column<float>(n);
    if (entry.has_classification) cloud.classification = Column<std::uint8_t>(n);
    for (ScalarColumn& column : cloud.scalars)
      column.data = ByteBuffer(n * scalarSize(column.type));
    std::uint64_t offset = entry.offset;
    forEachColumn(cloud, [&](std::byte* data, std::size_t size) {
      readAll(fd_, spill_.file_, offset, data, size);
      offset += size;
    });
    return cloud;
  }

  // The batch with its positions alone (the first column in the file).
  PointCloud loadPositions(const PointSpill::Batch& entry) {
    PointCloud cloud;
    cloud.count = entry.cloud.count;
    cloud.quantization = entry.cloud.quantization;
    cloud.source = entry.cloud.source;
    cloud.bounds = entry.cloud.bounds;
    if (!entry.in_file) {
      cloud.positions = entry.cloud.positions.clone();
      return cloud;
    }
    const std::size_t n = std::size_t(cloud.count);
    cloud.positions = Column<Int3>(n);
    readAll(fd_, spill_.file_, entry.offset, reinterpret_cast<std::byte*>(cloud.positions.data()),
            n * sizeof(Int3));
    return cloud;
  }

  PointSpill& spill_;
  bool last_pass_ = false;
  bool positions_only_ = false;
  int fd_ = -1;
  std::size_t next_batch_ = 0;
  PointCloud current_;
  std::uint64_t next_point_ = 0;
};

PointSpill::PointSpill(std::filesystem::path file, std::uint64_t memory_bytes,
                       Quantization quantization, CoordinateSystem crs)
    : file_(std::move(file)),
      memory_budget_(memory_bytes),
      quantization_(quantization),
      crs_(std::move(crs)) {}

PointSpill::~PointSpill() {
  if (fd_ >= 0) {
    ::close(fd_);
    std::error_code ignored;
    std::filesystem::remove(file_, ignored);
  }
}

void PointSpill::add(PointCloud batch) {
  Batch entry;
  entry.has_colors = batch.hasColors();
  entry.has_stored_colors = batch.hasStoredColors();
  entry.has_normals = batch.hasNormals();
  entry.has_intensity = batch.hasIntensity();
  entry.has_classification = batch.hasClassification();
  points_ += batch.count;
  const std::uint64_t bytes = pointCloudBytes(batch);
  // Once a batch goes to the file, the rest follow: the order of the batches is the file's.
  const bool to_file = fd_ >= 0 || memory_used_ + bytes > memory_budget_;
  if (to_file) {
    writeToFile(entry, batch);
  } else {
    memory_used_ += bytes;
    entry.cloud = std::move(batch);
  }
  batches_.push_back(std::move(entry));
}

void PointSpill::writeToFile(Batch& entry, const PointCloud& batch) {
  if (fd_ < 0) {
    fd_ = ::open(file_.c_str(), O_RDWR | O_CREAT | O_TRUNC | O_CLOEXEC, 0600);
    if (fd_ < 0) fail(file_, "cannot create");
  }
  entry.in_file = true;
  entry.offset = file_bytes_;
  entry.cloud = shapeOf(batch);
  forEachColumn(const_cast<PointCloud&>(batch), [&](const std::byte* data, std::size_t size) {
    writeAll(fd_, file_, data, size);
    file_bytes_ += size;
  });
}

std::unique_ptr<PointChunkSource> PointSpill::read(bool last_pass, bool positions_only) {
  assert(!(last_pass && positions_only) && "PointSpill::read: the last pass takes every column");
  return std::make_unique<SpillReader>(*this, last_pass, positions_only);
}

}  // namespace parallax
