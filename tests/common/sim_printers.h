#pragma once
// Lets GoogleTest print a Termination by name ("tilt") rather than as a byte.

#include <ostream>

#include "sim/env.h"

namespace flsd {

inline void PrintTo(Termination t, std::ostream* os) { *os << ToString(t); }

}  // namespace flsd
