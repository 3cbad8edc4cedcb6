// tear: the `simulation` block of a cut script, read into `SimulationOptions` (docs/simulation.md).
// Called by the cut script's parser; JSON stays out of the public headers.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "tear/simulation_options.h"

namespace tear {

/// Reads and checks a script's `simulation` object. Unknown keys, wrong types, non-finite numbers
/// and values outside their range (`simulation_limits`) throw an input `Error`
/// `<script_path>: simulation.<key path>: expected ..., got ...`. `source` of the result is
/// `script_path`. `frames`: the script's frames, which a mesh collider's sequence of files must
/// cover (0: as many as there are files from the first on).
SimulationOptions parse_simulation(const nlohmann::json& block, const std::string& script_path, int frames = 0);

}  // namespace tear
