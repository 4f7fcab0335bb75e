// Opening a Potree 2.0 directory: from a local path, an http(s) URL or memory.
#include <algorithm>
#include <string>

#include "core/byte_source_opener.h"
#include "core/error.h"
#include "core/url.h"
#include "lod/potree_reader.h"
#include "lod/potree_sources.h"

namespace parallax {
namespace {

// metadata.json of real clouds is a few kB; anything this large is not one.
constexpr std::uint64_t kMaxMetadataBytes = 64ull << 20;
// Fetched with the first request to hierarchy.bin: PotreeConverter's first chunk (4 levels, at
// most 585 entries of 22 bytes) fits, so opening costs one round trip for all three files.
constexpr std::uint64_t kHierarchyHeadBytes = 64u << 10;

const char* const kPotreeHint =
    "a Potree 2.0 directory holds metadata.json, hierarchy.bin and octree.bin";

// A file's InputError with the Potree hint added (a missing file is the usual cause).
[[noreturn]] void rethrowWithHint(const InputError& error, bool drop_offset) {
  InputErrorInfo info = error.info();
  if (drop_offset) info.byte_offset.reset();
  info.hint = info.hint.empty() ? kPotreeHint : info.hint + "; " + kPotreeHint;
  throw InputError(std::move(info));
}

std::filesystem::path directoryOf(const std::filesystem::path& path) {
  std::error_code error;
  if (path.filename() == "metadata.json" && !std::filesystem::is_directory(path, error)) {
    return path.parent_path().empty() ? std::filesystem::path(".") : path.parent_path();
  }
  return path;
}

std::string metadataText(const ByteSource& source) {
  if (source.size() > kMaxMetadataBytes) {
    throw InputError({.file = source.name(),
                      .expected = "a metadata.json of at most 64 MiB",
                      .found = std::to_string(source.size()) + " bytes"});
  }
  std::string text(source.size(), '\0');
  source.read(0, std::as_writable_bytes(std::span(text)), {.element = "metadata"});
  return text;
}

std::unique_ptr<Octree> openLocal(const std::filesystem::path& path) {
  const std::filesystem::path dir = directoryOf(path);
  std::error_code error;
  if (!std::filesystem::is_directory(dir, error)) {
    throw InputError({.file = dir.string(),
                      .expected = "a Potree 2.0 directory",
                      .found = std::filesystem::exists(dir, error) ? "a file" : "nothing",
                      .hint = kPotreeHint});
  }
  const std::filesystem::path metadata_file = dir / "metadata.json";
  PotreeSources sources;
  sources.location = dir.string();
  std::string text;
  try {
    const std::unique_ptr<ByteSource> metadata = openFileSource(metadata_file);
    text = metadataText(*metadata);
    sources.metadata_bytes = metadata->size();
  } catch (const InputError& e) {
    rethrowWithHint(e, false);
  }
  PotreeMetadata parsed = parsePotreeMetadata(text, metadata_file.string());
  try {
    sources.hierarchy = openFileSource(dir / "hierarchy.bin");
    sources.octree = openFileSource(dir / "octree.bin");
  } catch (const InputError& e) {
    rethrowWithHint(e, false);
  }
  return makePotreeOctree(std::move(parsed), std::move(sources));
}

// The URL of the directory (ending in '/') and its query.
UrlParts directoryUrl(const std::string& url) {
  UrlParts parts = splitUrl(url);
  if (parts.base.ends_with("/metadata.json")) {
    parts.base.resize(parts.base.size() - std::string_view("metadata.json").size());
  } else if (!parts.base.ends_with('/')) {
    parts.base += '/';
  }
  return parts;
}

std::unique_ptr<Octree> openUrl(const std::string& url) {
  const UrlParts parts = directoryUrl(url);
  auto file = [&](const char* name) { return parts.base + name + parts.query; };
  // Opened together: over HTTP the three probes go out in parallel (the first bytes of
  // metadata.json and hierarchy.bin with them).
  const ByteSourceRequest requests[] = {
      {file("metadata.json"), kMaxMetadataBytes},
      {file("hierarchy.bin"), kHierarchyHeadBytes},
      {file("octree.bin"), 0},
  };
  std::vector<std::unique_ptr<ByteSource>> opened;
  try {
    opened = openByteSources(requests);
  } catch (const InputError& e) {
    rethrowWithHint(e, true);
  }
  PotreeSources sources;
  sources.location = urlForMessages(parts.base + parts.query);
  sources.metadata_bytes = opened[0]->size();
  // The read is served by the bytes that came with the opening request.
  const std::string text = metadataText(*opened[0]);
  PotreeMetadata parsed = parsePotreeMetadata(text, opened[0]->name());
  sources.hierarchy = std::move(opened[1]);
  sources.octree = std::move(opened[2]);
  return makePotreeOctree(std::move(parsed), std::move(sources));
}

}  // namespace

std::string potreeFileLocation(const std::string& dir, std::string_view file) {
  if (isHttpUrl(dir)) {
    const UrlParts parts = directoryUrl(dir);
    return parts.base + std::string(file) + parts.query;
  }
  return (directoryOf(dir) / file).string();
}

bool isPotreeUrl(std::string_view url) {
  if (!isHttpUrl(url)) return false;
  const std::string name = urlFileName(url);
  return name.empty() || name == "metadata.json" || name.find('.') == std::string::npos;
}

bool isPotreeDirectory(const std::filesystem::path& path) {
  if (isHttpUrl(path.string())) return isPotreeUrl(path.string());
  std::error_code error;
  const std::filesystem::path dir = directoryOf(path);
  return std::filesystem::is_directory(dir, error) &&
         std::filesystem::is_regular_file(dir / "metadata.json", error);
}

std::unique_ptr<Octree> openPotree(const std::filesystem::path& path) {
  if (isHttpUrl(path.string())) return openUrl(path.string());
  return openLocal(path);
}

std::unique_ptr<Octree> openPotreeFromMemory(std::string metadata_json,
                                             std::vector<std::byte> hierarchy,
                                             std::vector<std::byte> octree,
                                             const std::string& name) {
  PotreeMetadata metadata = parsePotreeMetadata(metadata_json, name + "/metadata.json");
  PotreeSources sources;
  sources.location = name;
  sources.metadata_bytes = metadata_json.size();
  sources.hierarchy = makeMemorySource(std::move(hierarchy), name + "/hierarchy.bin");
  sources.octree = makeMemorySource(std::move(octree), name + "/octree.bin");
  return makePotreeOctree(std::move(metadata), std::move(sources));
}

}  // namespace parallax
