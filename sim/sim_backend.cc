#include "sim/sim_backend.h"

#include <limits>

namespace flsd {

EnvConfig SimBackend::MakeEnvConfig(const SimBackendConfig& config) {
  EnvConfig env;
  env.model = config.model;
  env.episode_steps = std::numeric_limits<int>::max();  // the server runs until it is stopped
  env.reset.joint_pos_scale = {1.0, 1.0};
  env.reset.base_velocity = 0.0;
  if (!config.randomize) env.randomization.DisableAll();
  return env;
}

SimBackend::SimBackend(const SimBackendConfig& config)
    : model_(LoadMjModel(config.model)), env_(*model_, MakeEnvConfig(config), config.seed) {}

void SimBackend::Send(const JointCommand& command) {
  if (!fault_.empty()) return;  // MuJoCo has reset its data: nothing to simulate until Reset()
  // Falls and tilts are the safety supervisor's to judge; only a broken simulation is a fault.
  if (env_.StepCommand(command) == Termination::kPhysics) {
    fault_ = "MuJoCo reported an unstable simulation at t = " + std::to_string(env_.state().time) +
             " s; reset the simulation";
  }
}

void SimBackend::Reset() {
  env_.Reset();
  fault_.clear();
}

}  // namespace flsd
