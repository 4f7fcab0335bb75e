#include "io/las_field_names.h"

#include <algorithm>
#include <cctype>
#include <string>

#include "core/column_names.h"

namespace parallax {
namespace {

// Lower case without '_', ' ', '-' and a leading "scalar_" (CloudCompare's prefix).
std::string bareFieldName(std::string_view name) {
  std::string text;
  for (char c : name) text += char(std::tolower(static_cast<unsigned char>(c)));
  if (text.starts_with("scalar_")) text.erase(0, 7);
  std::erase_if(text, [](char c) { return c == '_' || c == ' ' || c == '-'; });
  return text;
}

struct Spelling {
  const char* bare_name;  // as bareFieldName leaves it
  LasField field;
};

// The names a field goes by besides its model column's (which lasFieldNamed tries first): the
// single flag bits, which have no column of the model, PDAL's dimension names where they are not
// ours, and common aliases.
constexpr Spelling kOtherSpellings[] = {
    {"synthetic", LasField::Synthetic},
    {"keypoint", LasField::KeyPoint},
    {"withheld", LasField::Withheld},
    {"overlap", LasField::Overlap},
    {"scandirection", LasField::ScanDirection},
    {"classflags", LasField::ClassFlags},
    {"scanchannel", LasField::Channel},
    {"infrared", LasField::Nir},
    {"nearinfrared", LasField::Nir},
};

constexpr LasField kLastLasField = LasField::WaveDz;

}  // namespace

LasField lasFieldNamed(std::string_view name) {
  const std::string bare = bareFieldName(name);
  for (int i = 1; i <= int(kLastLasField); ++i) {
    const char* column = lasFieldColumn(LasField(i));
    if (column != nullptr && bare == bareFieldName(column)) return LasField(i);
  }
  for (const Spelling& spelling : kOtherSpellings) {
    if (bare == spelling.bare_name) return spelling.field;
  }
  return LasField::None;
}

const char* lasFieldColumn(LasField field) {
  namespace n = column_names;
  switch (field) {
    case LasField::ReturnNumber:
      return n::kReturnNumber;
    case LasField::NumberOfReturns:
      return n::kNumberOfReturns;
    case LasField::ScanDirection:
      return n::kScanDirectionFlag;
    case LasField::Edge:
      return n::kEdgeOfFlightLine;
    case LasField::ClassFlags:
      return n::kClassificationFlags;
    case LasField::Channel:
      return n::kScannerChannel;
    case LasField::ScanAngleRank:
      return n::kScanAngleRank;
    case LasField::ScanAngle:
      return n::kScanAngle;
    case LasField::UserData:
      return n::kUserData;
    case LasField::PointSourceId:
      return n::kPointSourceId;
    case LasField::GpsTime:
      return n::kGpsTime;
    case LasField::Nir:
      return n::kNir;
    case LasField::WaveIndex:
      return n::kWavePacketDescriptorIndex;
    case LasField::WaveOffset:
      return n::kWavePacketOffset;
    case LasField::WaveSize:
      return n::kWavePacketSize;
    case LasField::WaveLocation:
      return n::kReturnPointWaveformLocation;
    case LasField::WaveDx:
      return n::kWaveformDx;
    case LasField::WaveDy:
      return n::kWaveformDy;
    case LasField::WaveDz:
      return n::kWaveformDz;
    case LasField::None:
    case LasField::Synthetic:
    case LasField::KeyPoint:
    case LasField::Withheld:
    case LasField::Overlap:
      break;
  }
  return nullptr;
}

}  // namespace parallax
