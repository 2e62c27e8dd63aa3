#pragma once
#include <nlohmann/json.hpp>

namespace flsd {

// The machine a benchmark ran on: CPU model, core count, OS, so that figures carry their source.
nlohmann::json MachineDescription();

}  // namespace flsd
