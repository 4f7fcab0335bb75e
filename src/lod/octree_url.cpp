#include "lod/octree_url.h"

#include <algorithm>
#include <cctype>

#include "core/error.h"
#include "lod/potree_reader.h"
#include "net/url.h"

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
      return;
    case OctreeUrlKind::Copc:
      throw InputError({.file = urlForMessages(input),
                        .expected = "an octree this build reads over HTTP",
                        .found = "a COPC file: COPC over HTTP needs the COPC reader, which this "
                                 "build does not have yet",
                        .hint = "convert it to a Potree 2.0 directory and serve that, or download "
                                "the file"});
    case OctreeUrlKind::Other:
      throw InputError({.file = urlForMessages(input),
                        .expected = "the URL of a Potree 2.0 directory (.../cloud/ or "
                                    ".../cloud/metadata.json) or of a .copc.laz file",
                        .found = "a file '" + urlFileName(input) + "'",
                        .hint = "only octrees stream over HTTP; download other point files "
                                "first (a directory whose name has a dot needs its trailing "
                                "slash)"});
  }
}

std::unique_ptr<Octree> openOctreeUrl(const std::string& url) {
  checkOctreeUrl(url);
  return openPotree(url);
}

}  // namespace parallax
