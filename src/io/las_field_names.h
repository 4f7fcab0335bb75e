// The LAS point record's fields other than x y z, colour, intensity and classification, and every
// name a column may carry for one of them: the model's (core/column_names.h), PDAL's dimension
// names (GpsTime, ReturnNumber, ClassFlags, ScanChannel, Infrared: PDAL's PCD and text writers
// name fields so), and other tools' spellings (CloudCompare's "scalar_" prefix, "NearInfrared").
// One table for the readers that map a foreign field to the model's column (PCD) and for the LAS
// writer that places a column in a record: a spelling added here is known to both.
#pragma once

#include <string_view>

namespace parallax {

enum class LasField {
  None,
  ReturnNumber,
  NumberOfReturns,
  ScanDirection,
  Edge,
  ClassFlags,
  Synthetic,  // the single bits of the classification flags, as some tools write them apart
  KeyPoint,
  Withheld,
  Overlap,
  Channel,
  ScanAngleRank,
  ScanAngle,
  UserData,
  PointSourceId,
  GpsTime,
  Nir,
  WaveIndex,
  WaveOffset,
  WaveSize,
  WaveLocation,
  WaveDx,
  WaveDy,
  WaveDz
};

// The field a column's name stands for, or LasField::None. Case, '_', ' ' and '-' and a leading
// "scalar_" are ignored, so "GpsTime", "gps_time" and "scalar_GPS Time" are all gps_time.
LasField lasFieldNamed(std::string_view name);

// The model's column for `field` (a core/column_names.h name); null for None and for the single
// flag bits (Synthetic, KeyPoint, Withheld, Overlap), which the model holds in
// classification_flags and which a column of their own keeps under its own name.
const char* lasFieldColumn(LasField field);

}  // namespace parallax
