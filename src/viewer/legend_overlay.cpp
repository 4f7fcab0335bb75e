// The legend of the scalar colouring shown, drawn over the picture at the right of the window
// (render/scalar_legend.h's layout, the one `parallax render --legend` paints into its PNG),
// through Dear ImGui's background draw list: under the panel, over the points.
#include <imgui.h>

#include "render/overlay_font.h"
#include "render/scalar_legend.h"
#include "viewer/viewer_session.h"

namespace parallax::viewer_internal {

namespace {

ImU32 imColor(const Rgba8& c) {
  return IM_COL32(c.r, c.g, c.b, 255);
}

// The glyph metrics of the panel's font (Dear ImGui's default, the overlay font's source), for
// the layout: the labels are measured as ImGui draws them.
const OverlayFont& legendFont() {
  static const OverlayFont font;
  return font;
}

}  // namespace

void drawScalarLegendOverlay(Session& s) {
  if (!s.show_legend || !s.cloud || s.shown_scalar.field.empty() || !s.scalar_error.empty()) {
    return;
  }
  const ScalarLegend legend =
      scalarLegend(s.shown_scalar.field, s.shown_scalar.ramp, s.shown_scalar_range,
                   fieldUnit(s.shown_scalar.field, s.options->length_unit));
  const ImVec2 size = ImGui::GetIO().DisplaySize;
  const OverlayFont& font = legendFont();
  const LegendLayout layout = legendLayout(legend, font, int(size.x), int(size.y));
  if (layout.bar_height == 0) return;
  ImDrawList* draw = ImGui::GetBackgroundDrawList();
  const auto at = [](int x, int y) { return ImVec2(float(x), float(y)); };
  draw->AddRectFilled(at(layout.box_x, layout.box_y),
                      at(layout.box_x + layout.box_width, layout.box_y + layout.box_height),
                      IM_COL32(0, 0, 0, 153));
  for (int row = 0; row < layout.bar_height; ++row) {
    draw->AddRectFilled(at(layout.bar_x, layout.bar_y + row),
                        at(layout.bar_x + layout.bar_width, layout.bar_y + row + 1),
                        imColor(legendBarColor(legend, layout, row)));
  }
  const int line = int(font.lineHeight() + 0.999f);
  for (const auto& tick : legend.ticks) {
    const int y = layout.bar_y + legendRowOf(legend, layout, tick.value);
    draw->AddRectFilled(at(layout.bar_x + layout.bar_width, y), at(layout.label_x - 2, y + 1),
                        IM_COL32_WHITE);
    draw->AddText(at(layout.label_x, y - line / 2), IM_COL32_WHITE, tick.text.c_str());
  }
  draw->AddText(at(layout.title_x, layout.title_y), IM_COL32_WHITE, legend.title.c_str());
}

}  // namespace parallax::viewer_internal
