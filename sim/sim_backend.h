#pragma once
// The MuJoCo A1 as the server's backend. Each Send() advances the simulation by one control
// period (4 physics steps) holding that command, so the simulation runs in lockstep with the
// server's control loop: in real time when the loop is paced by the clock, faster in tests.

#include <string>

#include "robot/backend.h"
#include "sim/env.h"
#include "sim/sim_backend_config.h"

namespace flsd {

class SimBackend final : public Backend {
 public:
  explicit SimBackend(const SimBackendConfig& config);

  const char* name() const override { return "sim"; }
  void Send(const JointCommand& command) override;
  RobotState Read() override { return env_.state(); }
  std::string Fault() const override { return fault_; }
  // Places the robot standing in the default pose at the origin, at rest.
  bool CanReset() const override { return true; }
  void Reset() override;

  Env& env() { return env_; }

 private:
  static EnvConfig MakeEnvConfig(const SimBackendConfig& config);

  MjModelPtr model_;
  Env env_;
  std::string fault_;
};

}  // namespace flsd
