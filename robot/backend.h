#pragma once
#include "robot/robot_state.h"

namespace flsd {

// A robot the server can drive at the control rate: the MuJoCo A1 (sim/) or the real A1 (hw/).
class Backend {
 public:
  virtual ~Backend() = default;

  // Short name for logs and telemetry ("sim", "hw").
  virtual const char* name() const = 0;

  // Hands over the command to hold until the next call. Never blocks for long.
  virtual void Send(const JointCommand& command) = 0;

  // The latest measured (or estimated) state.
  virtual RobotState Read() = 0;
};

}  // namespace flsd
