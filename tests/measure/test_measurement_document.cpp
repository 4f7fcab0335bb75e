// The measurement file: a round trip that gives back the same doubles, and every malformed
// document an InputError naming the file, the JSON path and what was expected.
#include "measure/measurement_document.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "core/error.h"

namespace parallax {
namespace {

std::filesystem::path tempDir() {
  const std::filesystem::path dir = std::filesystem::path(PARALLAX_TEST_TMP) / "document";
  std::filesystem::create_directories(dir);
  return dir;
}

MeasurementDocument sample() {
  MeasurementDocument d;
  Camera camera;
  camera.lookAt({500010.125, 5000020.5, 150.0}, {500000.0, 5000000.0, 100.0}, {0, 0, 1});
  d.camera = camera;
  d.measurements.push_back({MeasurementKind::Distance,
                            "ridge",
                            {{500000.1234567891, 5000000.987654321, 101.001},
                             {500003.1, 5000004.2, 99.5},
                             {500010.0, 5000004.2, 99.5}}});
  d.measurements.push_back({MeasurementKind::Point, "", {{500001.0, 5000001.0, 100.0}}});
  d.measurements.push_back({MeasurementKind::Height,
                            "mast",
                            {{500001.0, 5000001.0, 100.0}, {500001.5, 5000001.0, 132.25}}});
  d.measurements.push_back(
      {MeasurementKind::Area, "roof", {{0.0, 0.0, 0.0}, {3.0, 0.0, 0.0}, {3.0, 4.0, 0.0}}});
  d.measurements.push_back({MeasurementKind::Angle, "", {{1, 0, 0}, {0, 0, 0}, {0, 1, 0}}});
  d.measurements.push_back(
      {MeasurementKind::Profile, "cut", {{0.0, 0.0, 0.0}, {10.0, 0.0, 0.0}}, 2.5});
  d.annotations.push_back({"antenna", {500001.5, 5000001.0, 132.25}, camera});
  d.annotations.push_back({"gate ünïcode", {500002.0, 5000003.0, 100.5}, std::nullopt});
  return d;
}

void expectSameCamera(const Camera& a, const Camera& b) {
  EXPECT_EQ(a.position, b.position);
  EXPECT_EQ(a.pivot, b.pivot);
  EXPECT_NEAR(glm::dot(a.orientation, b.orientation), 1.0, 1e-15);
  EXPECT_EQ(a.fov_y_deg, b.fov_y_deg);
}

TEST(MeasurementDocument, RoundTripKeepsEveryDouble) {
  const MeasurementDocument original = sample();
  const auto path = tempDir() / "round_trip.json";
  saveMeasurementDocument(original, path);
  EXPECT_FALSE(std::filesystem::exists(path.string() + ".partial"));
  const MeasurementDocument back = loadMeasurementDocument(path);
  EXPECT_EQ(back.measurements, original.measurements);
  ASSERT_EQ(back.annotations.size(), 2u);
  EXPECT_EQ(back.annotations[0].label, "antenna");
  EXPECT_EQ(back.annotations[0].position, original.annotations[0].position);
  ASSERT_TRUE(back.annotations[0].camera);
  expectSameCamera(*back.annotations[0].camera, *original.annotations[0].camera);
  EXPECT_EQ(back.annotations[1], original.annotations[1]);
  ASSERT_TRUE(back.camera);
  expectSameCamera(*back.camera, *original.camera);
}

TEST(MeasurementDocument, EmptyDocumentIsValid) {
  const MeasurementDocument d =
      parseMeasurementDocument(R"({"format": "parallax-measurements", "version": 1})", "e.json");
  EXPECT_FALSE(d.camera);
  EXPECT_TRUE(d.measurements.empty());
  EXPECT_TRUE(d.annotations.empty());
}

// The message of the InputError that parsing `text` throws; fails the test when none is thrown.
std::string errorOf(const std::string& text) {
  try {
    parseMeasurementDocument(text, "bad.json");
  } catch (const InputError& e) {
    EXPECT_EQ(e.info().file, "bad.json");
    return e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "not an InputError: " << e.what();
    return {};
  }
  ADD_FAILURE() << "no error for " << text;
  return {};
}

std::string withMeasurement(const std::string& measurement) {
  return R"({"format": "parallax-measurements", "version": 1, "measurements": [)" +
         std::string(R"({"kind": "point", "points": [[1, 2, 3]]}, )") + measurement + "]}";
}

TEST(MeasurementDocument, BadDocumentsNameThePathAndWhatWasExpected) {
  struct Case {
    std::string text, path, expected;
  };
  const std::vector<Case> cases{
      {"[1, 2]", "the top level", "a JSON object"},
      {R"({"version": 1})", "format", "parallax-measurements"},
      {R"({"format": "parallax-measurements", "version": 2})", "version", "version 1"},
      {R"({"format": "parallax-measurements", "version": 1, "extra": 0})", "the top level",
       "only the keys"},
      {withMeasurement(R"({"kind": "volume", "points": []})"), "measurements[1].kind",
       "point, distance, height, area, angle or profile"},
      {withMeasurement(R"({"points": [[0, 0, 0], [1, 1, 1]]})"), "measurements[1]", "a \"kind\""},
      {withMeasurement(R"({"kind": "distance", "points": [[0, 0, 0]]})"), "measurements[1].points",
       "at least 2 points for a distance"},
      {withMeasurement(R"({"kind": "angle", "points": [[0, 0, 0], [1, 0, 0]]})"),
       "measurements[1].points", "exactly 3 points for a angle"},
      {withMeasurement(R"({"kind": "distance", "points": [[0, 0, 0], [1, "a", 1]]})"),
       "measurements[1].points[1][1]", "a number"},
      {withMeasurement(R"({"kind": "distance", "points": [[0, 0, 0], [1, 1]]})"),
       "measurements[1].points[1]", "an array of 3 numbers"},
      {withMeasurement(R"({"kind": "profile", "points": [[0, 0, 0], [1, 1, 1]]})"),
       "measurements[1]", "corridor \"width\""},
      {withMeasurement(R"({"kind": "profile", "points": [[0, 0, 0], [1, 1, 1]], "width": -1})"),
       "measurements[1].width", "a width above 0"},
      {withMeasurement(R"({"kind": "distance", "points": [[0, 0, 0], [1, 1, 1]], "width": 1})"),
       "measurements[1].width", "only a profile has one"},
      {withMeasurement(R"({"kind": "distance", "points": [[0, 0, 0], [1, 1, 1]], "widht": 1})"),
       "measurements[1]", "only the keys"},
      {R"({"format": "parallax-measurements", "version": 1, "annotations": [{"label": 5,
          "position": [0, 0, 0]}]})",
       "annotations[0].label", "a string"},
      {R"({"format": "parallax-measurements", "version": 1, "annotations": [{"label": "a",
          "position": [0, 0, 0], "camera": {"position": [0, 0]}}]})",
       "annotations[0].camera", "a camera"},
      {R"({"format": "parallax-measurements", "version": 1, "camera": 3})", "camera", "a camera"},
      {R"({"format": "parallax-measurements", "version": 1, "camera": {"position": [0, 0, 0],
          "orientation_wxyz": [1e300, 1e300, 0, 0], "pivot": [0, 0, 0]}})",
       "camera", "a non-zero orientation quaternion"},
  };
  for (const Case& c : cases) {
    const std::string message = errorOf(c.text);
    EXPECT_NE(message.find("bad.json"), std::string::npos) << message;
    EXPECT_NE(message.find(c.path), std::string::npos) << "path " << c.path << ": " << message;
    EXPECT_NE(message.find(c.expected), std::string::npos)
        << "expected " << c.expected << ": " << message;
  }
}

TEST(MeasurementDocument, SyntaxErrorNamesTheLine) {
  try {
    parseMeasurementDocument("{\n  \"format\": \"parallax-measurements\",\n  \"version\": 1,,\n}",
                             "broken.json");
    FAIL() << "no error";
  } catch (const InputError& e) {
    ASSERT_TRUE(e.info().line);
    EXPECT_EQ(*e.info().line, 3u);
    EXPECT_NE(std::string(e.what()).find("broken.json"), std::string::npos);
  }
}

TEST(MeasurementDocument, NumberTooLargeForADoubleIsAnInputError) {
  const std::string text =
      R"({"format": "parallax-measurements", "version": 1, "measurements": [{"kind": "point",
          "points": [[1e400, 0, 0]]}]})";
  EXPECT_THROW(parseMeasurementDocument(text, "huge.json"), InputError);
}

TEST(MeasurementDocument, MissingFileIsAnInputError) {
  EXPECT_THROW(loadMeasurementDocument(tempDir() / "none.json"), InputError);
}

TEST(MeasurementDocument, SavingOverAnExistingFileReplacesItWhole) {
  const auto path = tempDir() / "replace.json";
  saveMeasurementDocument(sample(), path);
  MeasurementDocument smaller;
  smaller.annotations.push_back({"only", {1, 2, 3}, std::nullopt});
  saveMeasurementDocument(smaller, path);
  EXPECT_EQ(loadMeasurementDocument(path), smaller);
  // A folder where the file should go: an error, and the folder untouched.
  std::filesystem::create_directories(tempDir() / "folder.json");
  EXPECT_ANY_THROW(saveMeasurementDocument(smaller, tempDir() / "folder.json"));
  EXPECT_TRUE(std::filesystem::is_directory(tempDir() / "folder.json"));
}

}  // namespace
}  // namespace parallax
