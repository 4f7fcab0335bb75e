// Helper of the laz-perf tests (tests/io/js/run_laz_oracle.sh):
//   laz_test_tool records FILE.laz OUT.bin   every point record Parallax decodes from FILE.laz,
//                                            back to back (what laz_oracle.cjs dump writes)
#include <cstdio>
#include <cstring>
#include <exception>
#include <fstream>
#include <string>

#include "io/laz_test_files.h"

int main(int argc, char** argv) {
  if (argc != 4 || std::strcmp(argv[1], "records") != 0) {
    std::fprintf(stderr, "usage: %s records FILE.laz OUT.bin\n", argv[0]);
    return 2;
  }
  try {
    const std::string records = parallax::test::lazRecords(argv[2]);
    std::ofstream(argv[3], std::ios::binary).write(records.data(), std::streamsize(records.size()));
    std::printf("%s: %zu bytes of records (Parallax)\n", argv[2], records.size());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "FAILED: %s\n", e.what());
    return 1;
  }
  return 0;
}
