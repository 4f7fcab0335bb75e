#include "lod/octree_open.h"

#include "core/error.h"
#include "lod/copc_reader.h"
#include "lod/octree_url.h"
#include "lod/potree_reader.h"

namespace parallax {

OctreeFormat detectOctreeFormat(const std::filesystem::path& path) {
  switch (octreeUrlKind(path.string())) {  // a URL: by what it names (no request yet)
    case OctreeUrlKind::NotUrl:
      break;
    case OctreeUrlKind::Potree:
      return OctreeFormat::Potree;
    case OctreeUrlKind::Copc:
      return OctreeFormat::Copc;
    case OctreeUrlKind::Other:
      return OctreeFormat::None;
  }
  if (isPotreeDirectory(path)) return OctreeFormat::Potree;
  if (isCopcFile(path)) return OctreeFormat::Copc;
  return OctreeFormat::None;
}

std::unique_ptr<Octree> openOctree(const std::filesystem::path& path) {
  if (octreeUrlKind(path.string()) != OctreeUrlKind::NotUrl) return openOctreeUrl(path.string());
  switch (detectOctreeFormat(path)) {
    case OctreeFormat::Potree:
      return openPotree(path);
    case OctreeFormat::Copc:
      return openCopc(path);
    case OctreeFormat::None:
      break;
  }
  std::error_code error;
  if (std::filesystem::is_regular_file(path, error)) {
    throw InputError({.file = path.string(),
                      .expected = "an octree: a COPC file (LAS 1.4 with the COPC info VLR first)",
                      .found = "a file of another kind",
                      .hint = "`parallax convert FILE -o DIR` builds an octree of any point file"});
  }
  return openPotree(path);  // its error says what a Potree directory holds
}

}  // namespace parallax
