// The names of the point model's columns, defined once: what PointCloud::attributeNames() lists,
// what readers map a file's fields to, what writers, filters, processing steps and the renderer
// look up, and what users type (`--properties`, `--color-by`). A change here renames the
// attribute everywhere at once; a literal elsewhere would silently stop matching.
//
// Fixed columns of PointCloud: positions (x y z), colour (red green blue, alpha), normals
// (nx ny nz), intensity and classification. Every other attribute is a ScalarColumn under its
// own name; the LAS fields' names are here because several formats and modules share them.
#pragma once

namespace parallax::column_names {

// Positions.
inline constexpr const char* kX = "x";
inline constexpr const char* kY = "y";
inline constexpr const char* kZ = "z";
// Colour (PointCloud::colors); alpha only where the source had it.
inline constexpr const char* kRed = "red";
inline constexpr const char* kGreen = "green";
inline constexpr const char* kBlue = "blue";
inline constexpr const char* kAlpha = "alpha";
// Normals (PointCloud::normals).
inline constexpr const char* kNx = "nx";
inline constexpr const char* kNy = "ny";
inline constexpr const char* kNz = "nz";
// PointCloud::intensity and PointCloud::classification.
inline constexpr const char* kIntensity = "intensity";
inline constexpr const char* kClassification = "classification";

// The LAS point record's other fields, as scalar columns (any format may carry them: PLY and
// text by these names, E57 and PCD mapped to them).
inline constexpr const char* kReturnNumber = "return_number";
inline constexpr const char* kNumberOfReturns = "number_of_returns";
inline constexpr const char* kScanDirectionFlag = "scan_direction_flag";
inline constexpr const char* kEdgeOfFlightLine = "edge_of_flight_line";
inline constexpr const char* kClassificationFlags = "classification_flags";
inline constexpr const char* kScannerChannel = "scanner_channel";
inline constexpr const char* kScanAngleRank = "scan_angle_rank";
inline constexpr const char* kScanAngle = "scan_angle";
inline constexpr const char* kUserData = "user_data";
inline constexpr const char* kPointSourceId = "point_source_id";
inline constexpr const char* kGpsTime = "gps_time";
inline constexpr const char* kNir = "nir";
// The wave packet fields of point formats 4, 5, 9 and 10 (LAS 1.4 R15 Table 13).
inline constexpr const char* kWavePacketDescriptorIndex = "wave_packet_descriptor_index";
inline constexpr const char* kWavePacketOffset = "wave_packet_offset";
inline constexpr const char* kWavePacketSize = "wave_packet_size";
inline constexpr const char* kReturnPointWaveformLocation = "return_point_waveform_location";
inline constexpr const char* kWaveformDx = "waveform_dx";
inline constexpr const char* kWaveformDy = "waveform_dy";
inline constexpr const char* kWaveformDz = "waveform_dz";

// The scan a point came from, in files of several scans (E57, PTX): its index in file order.
inline constexpr const char* kScanIndex = "scan_index";

}  // namespace parallax::column_names
