// Files from other projects (laz-perf's, copc.js's and laspy's LAZ and COPC files, PDAL's E57,
// PCD, PTX and PTS files), read from PARALLAX_TEST_DATA and never committed into Parallax. The
// folder is resolved once, by cmake/ParallaxTestData.cmake (default ../shared/data beside the
// repository); a test target gets it with parallax_add_test(... TEST_DATA).
#pragma once

#include <filesystem>
#include <stdexcept>
#include <string>

namespace parallax::test {

// The path of `relative` (e.g. "laz/point10.las.laz") in PARALLAX_TEST_DATA. Throws, saying what
// to set, when the file is not there: the test fails with that message rather than with a
// reader's "cannot open".
inline std::filesystem::path testDataFile(const std::string& relative) {
  const std::filesystem::path path = std::filesystem::path(PARALLAX_TEST_DATA) / relative;
  if (!std::filesystem::is_regular_file(path)) {
    throw std::runtime_error(
        "test file " + path.string() +
        " not found: files from other projects are not in the repository; set "
        "PARALLAX_TEST_DATA to the folder holding laz/ and formats/ (in CI, ../shared/data beside "
        "the clone; -DPARALLAX_TEST_DATA=DIR or the environment at configure time) and "
        "reconfigure. README.md (Test data) says where each file comes from.");
  }
  return path;
}

}  // namespace parallax::test
