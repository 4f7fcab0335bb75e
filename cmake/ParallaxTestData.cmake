# Where the tests and the fuzz runs find test files that come from other projects (LAZ and COPC
# files of laz-perf, copc.js, laspy; E57, PCD, PTX and PTS files of PDAL). They are never
# committed into Parallax; README.md ("Test data") says where each comes from publicly.
#
# One setting, resolved here and only here: PARALLAX_TEST_DATA, a folder holding laz/ (and
# formats/). In order: -DPARALLAX_TEST_DATA=DIR, the environment variable PARALLAX_TEST_DATA at
# configure time, else ../shared/data beside the repository (where CI puts it). A relative path
# is taken from the repository root. The tests that read it fail, with a message saying what to
# set, where it holds no laz/ folder (the ctest fixture parallax_test_data and
# tests/support/test_data.h); scripts/test.sh takes the fuzz seeds' folder from the file written
# below, so it never resolves the setting itself.
if(NOT DEFINED PARALLAX_TEST_DATA)
  if(DEFINED ENV{PARALLAX_TEST_DATA} AND NOT "$ENV{PARALLAX_TEST_DATA}" STREQUAL "")
    set(PARALLAX_TEST_DATA "$ENV{PARALLAX_TEST_DATA}")
  else()
    set(PARALLAX_TEST_DATA "../shared/data")
  endif()
endif()
get_filename_component(PARALLAX_TEST_DATA "${PARALLAX_TEST_DATA}" ABSOLUTE
                       BASE_DIR "${PROJECT_SOURCE_DIR}")
file(WRITE ${PROJECT_BINARY_DIR}/parallax_test_data.txt "${PARALLAX_TEST_DATA}\n")
if(NOT IS_DIRECTORY "${PARALLAX_TEST_DATA}/laz")
  message(STATUS "PARALLAX_TEST_DATA: no laz/ folder in ${PARALLAX_TEST_DATA}; the tests that "
                 "read other projects' files will fail until it is set (see README.md, Test data)")
endif()
