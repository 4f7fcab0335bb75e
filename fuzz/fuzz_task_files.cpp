// libFuzzer target for the files a distributed conversion's tasks read (lod/distributed_plan.h,
// lod/distributed_task_files.h): plan.json, a build's nodes file, a range's counts and stats,
// chunks.json. Any bytes must give their contents or an InputError (the plan) or a
// std::runtime_error naming the file (the others); never a crash, an out-of-bounds read or an
// allocation beyond what the file's size justifies.
//
// Input framing (seeds in fuzz/corpus/task_files/): one byte choosing the reader (its value
// modulo 5: plan, nodes, counts, chunks, stats), then the file's bytes. The readers take paths:
// the bytes are written to a file of this process first.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/error.h"
#include "lod/convert_stages.h"
#include "lod/distributed_plan.h"
#include "lod/distributed_task_files.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  static const std::filesystem::path path =
      std::filesystem::temp_directory_path() /
      ("parallax_fuzz_task_file_" + std::to_string(::getpid()));
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data + 1), std::streamsize(size - 1));
  }
  try {
    switch (data[0] % 5) {
      case 0:
        parallax::readDistributedPlan(path);
        break;
      case 1:
        parallax::readGroupNodes(path);
        parallax::readGroupPartHead(path);
        break;
      case 2: {
        std::vector<std::uint64_t> counts(parallax::ConvertPlan::kGridCells, 0);
        parallax::addCounts(path, counts);
        break;
      }
      case 3:
        parallax::readChunkGroups(path);
        break;
      default: {
        parallax::AttributeStats stats;  // the five attributes of the seed's layout
        stats.min.assign(5, {0, 0, 0});
        stats.max.assign(5, {0, 0, 0});
        parallax::mergeStats(path, stats);
      }
    }
  } catch (const parallax::InputError&) {
  } catch (const std::runtime_error&) {
  }
  return 0;
}
