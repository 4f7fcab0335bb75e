// Where the commands' stage progress goes when a host runs them in its own process and shows
// progress its own way (the Python module's progress callbacks) rather than as bars on stderr.
#pragma once

#include <cstdint>
#include <functional>
#include <string>

namespace parallax::cli {

// Called with a stage's label ("counting", "indexing", a processing step, ...), the points done
// and its total (0: unknown), from whichever thread advances the stage, one call at a time per
// stage, at most every 1/200 of the total (2^20 points when unknown), and last with the final
// count. While one is set, stageBars (progress_options.h) reports to it, also under --quiet; an
// empty function restores the bars. Set it only while no command runs.
using ProgressObserver =
    std::function<void(const std::string& label, std::uint64_t done, std::uint64_t total)>;
void setProgressObserver(ProgressObserver observer);

}  // namespace parallax::cli
