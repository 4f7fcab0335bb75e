#include "viewer/large_cloud.h"

#include <stdlib.h>
#include <unistd.h>

#include <cstdio>
#include <stdexcept>
#include <system_error>

#include "io/las_header.h"
#include "io/mapped_file.h"
#include "io/ply_header.h"
#include "io/point_file.h"
#include "lod/octree_cache.h"

namespace parallax {

std::optional<std::uint64_t> headerPointCount(const std::filesystem::path& path) {
  try {
    switch (detectPointFormat(path)) {
      case PointFormat::Ply: {
        const MappedFile file(path);
        const PlyHeader header = parsePlyHeader(file.bytes(), path.string());
        const int element = header.pointElement();
        if (element < 0) return std::nullopt;
        return header.elements[std::size_t(element)].count;
      }
      case PointFormat::Las:
      case PointFormat::Laz:
        return readLasHeader(path).point_count;
      default:
        return std::nullopt;
    }
  } catch (const std::exception&) {
    return std::nullopt;  // the ordinary read says what is wrong
  }
}

OctreeLocation::OctreeLocation(const std::filesystem::path& input,
                               const OctreeCacheSettings& settings)
    : input_(std::filesystem::absolute(input)) {
  if (!settings.use_cache) {
    std::string pattern = (std::filesystem::temp_directory_path() / "parallax-octree-XXXXXX");
    if (!mkdtemp(pattern.data())) {
      throw std::system_error(
          errno, std::generic_category(),
          "cannot create a temporary folder for the octree of " + input.string());
    }
    temporary_root_ = pattern;
    directory_ = temporary_root_ / input.filename().replace_extension();
    return;
  }
  std::filesystem::path root = settings.cache_dir;
  if (root.empty()) {
    const auto found = octreeCacheRoot();
    if (!found) {
      throw std::runtime_error(
          "no cache folder for the octree of " + input.string() +
          ": neither XDG_CACHE_HOME nor HOME is set (use --cache-dir DIR or --no-cache)");
    }
    root = *found;
  }
  directory_ = cachedOctreePath(root, input_);
}

OctreeLocation::~OctreeLocation() {
  if (temporary_root_.empty()) return;
  std::error_code ignored;
  std::filesystem::remove_all(temporary_root_, ignored);
}

void OctreeLocation::abandon() const noexcept {
  std::error_code ignored;
  if (!temporary_root_.empty()) {
    std::filesystem::remove_all(temporary_root_, ignored);
    return;
  }
  // The converter's temporary name (lod/potree_converter.h).
  std::string partial = ".";
  partial += directory_.filename().string();
  partial += ".partial-";
  partial += std::to_string(::getpid());
  std::filesystem::remove_all(directory_.parent_path() / partial, ignored);
}

bool OctreeLocation::complete() const {
  return isCompleteOctree(directory_);
}

bool ensureOctree(const OctreeLocation& location, const OctreeBuildOptions& build,
                  const ProgressFactory& progress) {
  if (location.complete()) return false;
  std::filesystem::create_directories(location.directory().parent_path());
  PotreeConvertOptions options;
  options.build = build;
  options.progress = progress;
  options.name = location.input().filename().string();
  convertToPotree({ConvertInput{location.input(), {}}}, location.directory(), options);
  return true;
}

// One converter stage's progress, written into the build's counters.
class BackgroundOctreeBuild::StageProgress final : public Progress {
 public:
  explicit StageProgress(BackgroundOctreeBuild& build) : build_(build) {}
  void advance(std::uint64_t amount) override { build_.done_ += amount; }

 private:
  BackgroundOctreeBuild& build_;
};

BackgroundOctreeBuild::BackgroundOctreeBuild(std::unique_ptr<OctreeLocation> location,
                                             const OctreeBuildOptions& build)
    : location_(std::move(location)), start_(std::chrono::steady_clock::now()) {
  thread_ = std::thread([this, build] {
    const ProgressFactory progress = [this](const std::string& stage, std::uint64_t total) {
      {
        const std::lock_guard lock(mutex_);
        stage_ = stage;
      }
      done_ = 0;
      total_ = total;
      return std::make_unique<StageProgress>(*this);
    };
    try {
      ensureOctree(*location_, build, progress);
    } catch (const std::exception& e) {
      const std::lock_guard lock(mutex_);
      error_ = e.what();
      if (error_.empty()) error_ = "the conversion failed";
    }
    finished_ = true;
  });
}

BackgroundOctreeBuild::~BackgroundOctreeBuild() {
  if (thread_.joinable()) thread_.join();
}

std::unique_ptr<OctreeLocation> BackgroundOctreeBuild::takeLocation() {
  if (thread_.joinable()) thread_.join();
  return std::move(location_);
}

BackgroundOctreeBuild::Status BackgroundOctreeBuild::status() const {
  Status status;
  status.finished = finished_;
  status.done = done_;
  status.total = total_;
  const std::lock_guard lock(mutex_);
  status.stage = stage_;
  status.error = error_;
  return status;
}

double BackgroundOctreeBuild::secondsElapsed() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

}  // namespace parallax
