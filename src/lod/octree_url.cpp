#include "lod/octree_url.h"

#include <algorithm>
#include <cctype>

#include "core/byte_source_opener.h"
#include "core/error.h"
#include "core/url.h"
#include "lod/copc_reader.h"
#include "lod/potree_reader.h"

namespace parallax {

OctreeUrlKind octreeUrlKind(std::string_view input) {
  if (!isHttpUrl(input)) return OctreeUrlKind::NotUrl;
  std::string name = urlFileName(input);
  std::transform(name.begin(), name.end(), name.begin(),
                 [](unsigned char c) { return char(std::tolower(c)); });
  if (name.ends_with(".copc.laz")) return OctreeUrlKind::Copc;
  return isPotreeUrl(input) ? OctreeUrlKind::Potree : OctreeUrlKind::Other;
}

void checkOctreeUrl(std::string_view input) {
  switch (octreeUrlKind(input)) {
    case OctreeUrlKind::NotUrl:
    case OctreeUrlKind::Potree:
    case OctreeUrlKind::Copc:
      return;
    case OctreeUrlKind::Other:
      throw InputError({.file = urlForMessages(input),
                        .expected = "the URL of a Potree 2.0 directory (.../cloud/ or "
                                    ".../cloud/metadata.json) or of a .copc.laz file",
                        .found = "a file '" + urlFileName(input) + "'",
                        .hint = "only octrees stream over HTTP here; `parallax info`, "
                                "`render`, `pick` and `convert` read any point file from a URL "
                                "(a directory whose name has a dot needs its trailing slash)"});
  }
}

std::unique_ptr<Octree> openOctreeUrl(const std::string& url) {
  checkOctreeUrl(url);
  if (octreeUrlKind(url) == OctreeUrlKind::Copc) {
    // The header, the VLRs and the root hierarchy page are usually in the first 64 KiB: one
    // request for all three.
    return openCopc(openByteSource(url, 64 << 10));
  }
  return openPotree(url);
}

}  // namespace parallax
