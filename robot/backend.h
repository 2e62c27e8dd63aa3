#pragma once
#include <string>

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

  // Why the state cannot be trusted (a stale sensor, an unstable simulation), or empty. The
  // server's safety supervisor damps the robot while this is not empty.
  virtual std::string Fault() const { return {}; }

  // Whether Reset() can put the robot back on its feet (the simulator can; a real robot cannot).
  virtual bool CanReset() const { return false; }
  virtual void Reset() {}
};

}  // namespace flsd
