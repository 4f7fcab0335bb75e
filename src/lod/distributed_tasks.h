// The tasks of a distributed conversion (distributed_plan.h lists them and their files): each
// runs one stage of the local conversion (convert_stages.h) on one range of the inputs or one
// group of chunks, reading the files earlier tasks wrote in the plan's work directory.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "lod/convert_stages.h"
#include "lod/distributed_plan.h"

namespace parallax {

// The stages, in the order they run; "scan", "count", "distribute" take a range, "build" and
// "place" a group, the others part 0 only.
const std::vector<std::string_view>& distributedStages();

// How many parts a stage has: the plan's ranges, the groups chunks.json made (readable once the
// chunks task ran), or 1.
std::size_t distributedStageParts(const DistributedPlan& plan, std::string_view stage);

// Runs part `part` of `stage`. `inputs` are the plan's inputs with their filters (the command
// line builds them from plan.filter). Returns a one-line JSON summary (points, seconds; for a
// build, whether it wrote in place: "placed").
// Throws InputError for bad input (the message the local conversion gives), std::runtime_error
// for missing or damaged task files, std::invalid_argument for an unknown stage or part.
std::string runDistributedTask(const DistributedPlan& plan, const std::vector<ConvertInput>& inputs,
                               std::string_view stage, std::size_t part);

}  // namespace parallax
