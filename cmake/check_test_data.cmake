# ctest fixture parallax_test_data (cmake -DDIR=... -P check_test_data.cmake): fails, saying what
# to set, when the folder of other projects' test files is missing. Tests that read it require the
# fixture, so without it they are reported as not run (a failure), never as passed.
if(NOT EXISTS "${DIR}/laz/README.md" OR NOT EXISTS "${DIR}/formats/README.md")
  message(FATAL_ERROR
    "The test files from other projects (laz-perf, copc.js, laspy, PDAL) are not in the "
    "repository and were not found at ${DIR} (laz/ and formats/). Set PARALLAX_TEST_DATA to the folder holding "
    "laz/ and formats/ (in CI, ../shared/data beside the clone): -DPARALLAX_TEST_DATA=DIR or the "
    "environment variable at configure time, then reconfigure. README.md (Test data) says where "
    "each file comes from.")
endif()
message(STATUS "test data: ${DIR}")
