// A cloud's coordinate reference system (CRS), as its source states it, in a form that travels
// with the points through a conversion: from a LAS file (and LAZ, COPC: the same records) to the
// octree builder (lod/convert_stages.h: PointStream::crs, ConvertPlan::crs), into Potree's
// metadata.json `projection`, and into LAS (LAZ, COPC) outputs, which copy its records.
//
// PLY and text files state no CRS: theirs is empty.
#pragma once

#include <string>
#include <vector>

#include "io/las_header.h"

namespace parallax {

struct CoordinateSystem {
  // What the records say: OGC WKT, or GeoTIFF keys (EPSG codes, citation).
  LasCrs description;
  // The LASF_Projection records (2112 WKT, 34735 GeoKeyDirectoryTag, 34736 doubles, 34737
  // text) as the source wrote them, payloads included: what a LAS writer copies.
  std::vector<LasVlr> records;

  bool empty() const { return records.empty(); }
  // "NAD83 / UTM zone 15N (WKT)", "EPSG:26915 (GeoTIFF keys)", "none".
  std::string summary() const { return description.summary(); }
  // The same records (ids and payloads): two inputs that may be merged.
  bool sameAs(const CoordinateSystem& other) const;
};

// The CRS of a LAS file's header: its LASF_Projection VLRs and EVLRs.
CoordinateSystem coordinateSystemOf(const LasHeader& header);

// The `projection` string of Potree 2.0's metadata.json. PotreeConverter 2 writes what its
// --projection option is given (empty by default); Potree's viewer hands it to proj4js. So:
//   - the WKT, as written, when the file has one (proj4js reads WKT);
//   - from GeoTIFF keys, a proj4 string where the EPSG code has a fixed one (the definitions of
//     PROJ's former "epsg" init file): WGS 84 and NAD83 geographic (4326, 4269), UTM zones of
//     WGS 84 (326zz north, 327zz south), NAD83 (269zz, zones 1-23), NAD27 (267zz, zones 3-22)
//     and ETRS89 (258zz, zones 28-38), and Web Mercator (3857);
//   - "EPSG:<code>" for any other projected (else geographic) code, for clients with an EPSG
//     database;
//   - "" without a CRS, or with a user-defined one (code 32767), which has no short name (a
//     user-defined projected CRS is not named after its geographic base either).
// A vertical datum (VerticalCSTypeGeoKey) has no place in a proj4 string: it stays in the LAS
// records only.
std::string potreeProjection(const LasCrs& crs);

}  // namespace parallax
