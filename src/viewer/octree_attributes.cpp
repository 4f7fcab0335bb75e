// The viewer reads an octree's nodes with what its look draws, and again when the look changes
// (issue 25 item 4). COPC decodes only the LAZ layers asked for (Octree::selectAttributes), so a
// format-7 file shown in RGB never decodes its intensity, GPS time or classification layers;
// Potree octrees ignore the selection (a node costs the same whatever is asked) and are never
// read again. Picking and height profiles read nodes whole (Octree::loadNodeWhole): they report
// every attribute of a point, whatever the picture shows.
//
// Why a new LodScene for a new selection: a scene's loader stages chunks with the octree's
// columns as they were when it started (render/node_loader.h), and selectAttributes must not
// run beside loader threads. The old scene's loader is stopped first (LodScene::stopLoading), so
// its GPU buffers stay and its last picture is drawn, in the look it was loaded for, until the
// new scene has as much on screen. Nodes are read with what the look needs now, not with the
// union of every look shown: switching back costs a reload, and a session that tried every
// colour mode does not end up decoding everything.
#include <algorithm>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "render/render_settings.h"
#include "viewer/joined_names.h"
#include "viewer/viewer_session.h"

namespace parallax::viewer_internal {
namespace {

// The attributes the look needs, in the order the octree holds them; scalar colourings are not
// drawn on octrees (viewer.cpp: showOpenedOctree), so their field is not read for them.
std::vector<std::string> attributesNeeded(const Session& s) {
  RenderSettings look = s.settings;
  look.scalar = {};
  const AttributeSelection drawn = attributesDrawn(look);
  std::vector<std::string> needed;
  for (const std::string& name : s.octree_attributes) {
    if (drawn.wants(name)) needed.push_back(name);
  }
  return needed;
}

// Selects `needed` on the octree (no loader may be reading it) and starts a scene on it.
void loadWith(Session& s, const std::vector<std::string>& needed) {
  s.octree->selectAttributes(AttributeSelection::only(needed));
  s.octree_read = s.octree->info().attributes;
  s.lod = std::make_unique<LodScene>(*s.octree);
  s.pick_source.reset();
  s.drawn.reset();
  std::vector<std::string> skipped;
  for (const std::string& name : s.octree_attributes) {
    if (std::find(s.octree_read.begin(), s.octree_read.end(), name) == s.octree_read.end()) {
      skipped.push_back(name);
    }
  }
  // Tests and users read what was decoded here: the counterpart of `render`'s selection.
  std::fprintf(stderr, "parallax view: octree nodes read with %s%s%s\n",
               joinedNames(s.octree_read).c_str(),
               skipped.empty() ? "" : "; not read: ", joinedNames(skipped).c_str());
}

}  // namespace

void startLodScene(Session& s) {
  s.previous_lod.reset();
  s.octree_attributes = s.octree->info().attributes;
  loadWith(s, attributesNeeded(s));
}

void updateLodAttributes(Session& s) {
  if (!s.lod || !s.octree) return;
  const std::vector<std::string> needed = attributesNeeded(s);
  const bool missing = std::any_of(needed.begin(), needed.end(), [&](const std::string& name) {
    return std::find(s.octree_read.begin(), s.octree_read.end(), name) == s.octree_read.end();
  });
  if (!missing) return;
  s.lod->stopLoading();
  // The picture on screen stays: the scene that drew it (or, while an earlier switch is still
  // loading, the scene before that, whose picture is the one shown).
  const bool shown = s.drawn && s.drawn->scene == s.lod.get() && !s.lod->drawSet().items.empty();
  if (!s.previous_lod && shown) {
    s.previous_lod = Session::PreviousLod{.scene = std::move(s.lod),
                                          .settings = s.drawn->settings,
                                          .points = s.lod_stats.drawn_points};
  }
  s.lod.reset();
  loadWith(s, needed);
}

const DrawSet* previousLodPicture(Session& s, const RenderSettings*& look, bool& changed) {
  if (!s.previous_lod) return nullptr;
  if (s.lod->complete() || s.lod->stats().drawn_points >= s.previous_lod->points) {
    s.previous_lod.reset();
    changed = true;  // the new scene's picture starts afresh, in the look asked
    return nullptr;
  }
  look = &s.previous_lod->settings;
  return &s.previous_lod->scene->drawSet();
}

}  // namespace parallax::viewer_internal
