#include "io/coordinate_system.h"

#include <optional>

namespace parallax {
namespace {

constexpr std::uint16_t kUserDefined = 32767;

std::string utm(int zone, bool south, const char* datum) {
  std::string text = "+proj=utm +zone=" + std::to_string(zone);
  if (south) text += " +south";
  text += datum;
  text += " +units=m +no_defs";
  return text;
}

// A proj4 string for the codes that have a fixed one (see coordinate_system.h).
std::optional<std::string> proj4For(int code) {
  if (code >= 32601 && code <= 32660) return utm(code - 32600, false, " +datum=WGS84");
  if (code >= 32701 && code <= 32760) return utm(code - 32700, true, " +datum=WGS84");
  if (code >= 26901 && code <= 26923) return utm(code - 26900, false, " +datum=NAD83");
  if (code >= 26703 && code <= 26722) return utm(code - 26700, false, " +datum=NAD27");
  if (code >= 25828 && code <= 25838) {
    return utm(code - 25800, false, " +ellps=GRS80 +towgs84=0,0,0,0,0,0,0");
  }
  switch (code) {
    case 4326:
      return "+proj=longlat +datum=WGS84 +no_defs";
    case 4269:
      return "+proj=longlat +datum=NAD83 +no_defs";
    case 3857:
      return "+proj=merc +a=6378137 +b=6378137 +lat_ts=0 +lon_0=0 +x_0=0 +y_0=0 +k=1 +units=m "
             "+nadgrids=@null +wktext +no_defs";
    default:
      return std::nullopt;
  }
}

}  // namespace

bool CoordinateSystem::sameAs(const CoordinateSystem& other) const {
  if (records.size() != other.records.size()) return false;
  for (std::size_t i = 0; i < records.size(); ++i) {
    if (records[i].record_id != other.records[i].record_id ||
        records[i].data != other.records[i].data) {
      return false;
    }
  }
  return true;
}

CoordinateSystem coordinateSystemOf(const LasHeader& header) {
  CoordinateSystem crs;
  crs.description = header.crs;
  for (const LasVlr& vlr : header.vlrs) {
    if (vlr.user_id == "LASF_Projection" && !vlr.data.empty()) crs.records.push_back(vlr);
  }
  return crs;
}

std::string potreeProjection(const LasCrs& crs) {
  if (!crs.wkt.empty()) return crs.wkt;
  // A projected CRS names its code (a user-defined one cannot be named: its geographic base is
  // not the CRS); a geographic CRS alone, its own.
  const std::optional<std::uint16_t> code =
      crs.projected_epsg ? crs.projected_epsg : crs.geographic_epsg;
  if (!code || *code == kUserDefined || *code == 0) return "";
  if (const auto proj4 = proj4For(*code)) return *proj4;
  return "EPSG:" + std::to_string(*code);
}

}  // namespace parallax
