#pragma once
#include <cstdint>

namespace flsd {

struct SimDemoOptions {
  double stand_seconds = 5.0;
  double random_seconds = 10.0;
  uint64_t seed = 1;
};

// Holds the nominal A1 standing under PD control, then drives it with random joint targets, and
// prints what happened: falls and their causes, base height, foot contacts, simulation speed.
// Returns 0 when the robot stood for the whole first phase.
int RunSimDemo(const SimDemoOptions& options);

}  // namespace flsd
