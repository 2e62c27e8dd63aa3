#include "tools/flsd/sim_demo.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <map>
#include <memory>
#include <string>

#include "core/rng.h"
#include "robot/observation.h"
#include "sim/env.h"
#include "tools/flsd/subcommands.h"

namespace flsd {
namespace {

struct PhaseReport {
  int steps = 0;
  int falls = 0;
  std::map<std::string, int> endings;
  double height_sum = 0.0, height_min = 1e9, height_max = -1e9;
  long feet_down = 0;
  double wall_seconds = 0.0;
};

// Runs `steps` control steps with actions from `policy`, resetting after every ending.
template <class Policy>
PhaseReport RunPhase(Env& env, int steps, Policy policy) {
  PhaseReport r;
  float action[kActionSize];
  const auto start = std::chrono::steady_clock::now();
  for (int t = 0; t < steps; ++t) {
    policy(action);
    const Termination ending = env.Step(action);
    const RobotState& s = env.state();
    r.height_sum += s.base_position.z();
    r.height_min = std::min(r.height_min, s.base_position.z());
    r.height_max = std::max(r.height_max, s.base_position.z());
    r.feet_down += std::count(s.foot_contact.begin(), s.foot_contact.end(), true);
    if (ending != Termination::kNone) {
      ++r.endings[ToString(ending)];
      r.falls += IsFailure(ending);
      env.Reset();
    }
    ++r.steps;
  }
  r.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return r;
}

void Print(const char* title, const PhaseReport& r) {
  std::printf("%s\n", title);
  std::printf("  simulated %.1f s in %.3f s of wall time: %.0f control steps/s, %.0fx real time\n",
              r.steps * a1::kControlDt, r.wall_seconds, r.steps / r.wall_seconds,
              r.steps * a1::kControlDt / r.wall_seconds);
  std::printf("  base height: mean %.3f m, min %.3f m, max %.3f m\n", r.height_sum / r.steps,
              r.height_min, r.height_max);
  std::printf("  feet on the ground: %.2f of 4 on average\n", double(r.feet_down) / r.steps);
  std::printf("  falls: %d", r.falls);
  for (const auto& [why, count] : r.endings) std::printf("  [%s: %d]", why.c_str(), count);
  std::printf("\n");
}

}  // namespace

int RunSimDemo(const SimDemoOptions& options) {
  const MjModelPtr model = LoadMjModel(EnvConfig{}.model);
  EnvConfig config;
  config.randomization.DisableAll();
  config.reset.base_velocity = 0.0;
  config.reset.joint_pos_scale = {1.0, 1.0};
  config.episode_steps = 1000000;
  Env env(*model, config, options.seed);

  std::printf("FLSD simulator demo: MuJoCo %s, A1 with PD Kp %.0f, Kd %.1f, %d physics steps of %.0f ms "
              "per %.0f ms control step\n\n",
              mj_versionString(), a1::kKp, a1::kKd, a1::kDecimation, a1::kPhysicsDt * 1e3,
              a1::kControlDt * 1e3);

  const int stand_steps = static_cast<int>(options.stand_seconds / a1::kControlDt);
  const PhaseReport stand =
      RunPhase(env, stand_steps, [](float* a) { std::fill(a, a + kActionSize, 0.0f); });
  Print("1. Standing: PD to the default pose (zero action)", stand);

  Rng rng(options.seed);
  const int random_steps = static_cast<int>(options.random_seconds / a1::kControlDt);
  const PhaseReport random = RunPhase(env, random_steps, [&](float* a) {
    for (int j = 0; j < kActionSize; ++j) a[j] = static_cast<float>(Uniform(rng, -1.0, 1.0));
  });
  Print("\n2. Random joint targets: default pose + 0.25 rad x U(-1, 1), new every 20 ms", random);

  const bool stood = stand.falls == 0;
  std::printf("\n%s\n", stood ? "The A1 stood for the whole first phase." : "The A1 fell while standing.");
  return stood ? 0 : 1;
}

namespace cli {

void AddDemo(CLI::App& app, Subcommands& out) {
  auto demo = std::make_shared<SimDemoOptions>();
  CLI::App* cmd = app.add_subcommand("demo", "Stand the simulated A1, then drive it with random targets");
  cmd->add_option("--stand-seconds", demo->stand_seconds, "Length of the standing phase")->check(CLI::Range(0.02, 3600.0));
  cmd->add_option("--random-seconds", demo->random_seconds, "Length of the random-target phase")
      ->check(CLI::Range(0.02, 3600.0));
  cmd->add_option("--seed", demo->seed, "Random seed");
  out.push_back({cmd, [demo] { return RunSimDemo(*demo); }});
}

}  // namespace cli
}  // namespace flsd
