#include "bench/sim_bench.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <thread>
#include <vector>

#include "bench/machine.h"
#include "core/config.h"
#include "core/rng.h"
#include "robot/observation.h"
#include "sim/vec_env.h"

namespace flsd {
namespace {

using Clock = std::chrono::steady_clock;

double Seconds(Clock::time_point since) {
  return std::chrono::duration<double>(Clock::now() - since).count();
}

struct Tally {
  double steps = 0.0;
  double seconds = 0.0;
  double contacts = 0.0;
};

// Control steps of the full VecEnv in `seconds`, random actions drawn ahead of time.
void TimeVecEnv(VecEnv& vec, double seconds, Rng& rng, Tally& tally) {
  const int n = vec.num_envs();
  std::vector<float> actions(16 * n * kActionSize);
  for (float& a : actions) a = static_cast<float>(Uniform(rng, -1.0, 1.0));
  const Clock::time_point start = Clock::now();
  long steps = 0;
  while (Seconds(start) < seconds) {
    vec.Step(&actions[(steps % 16) * n * kActionSize]);
    ++steps;
  }
  tally.seconds += Seconds(start);
  tally.steps += static_cast<double>(steps) * n;
}

// A simulation for the ceiling: a model and the state it starts (and restarts after a fall) from.
struct BareSim {
  const mjModel* model;
  const mjData* start;
};

// One thread of the ceiling: bare mj_step on its share of simulations, round robin, with a PD
// torque toward a random target computed once per control step and held for its 4 physics steps.
void BareStepLoop(const std::vector<BareSim>& sims, int begin, int end, const A1ModelIndex& index,
                  double seconds, uint64_t seed, std::atomic<long>& steps_out,
                  std::atomic<long>& contacts_out) {
  std::vector<MjDataPtr> data;
  for (int i = begin; i < end; ++i) {
    data.emplace_back(mj_makeData(sims[i].model));
    mj_copyData(data.back().get(), sims[i].model, sims[i].start);
  }
  Rng rng(seed);
  long steps = 0, contacts = 0;
  const Clock::time_point start = Clock::now();
  for (long round = 0; round % 64 != 0 || Seconds(start) < seconds; ++round) {
    for (int i = begin; i < end; ++i) {
      const mjModel& m = *sims[i].model;
      mjData& d = *data[i - begin];
      if (d.qpos[index.root_qpos + 2] < 0.15) mj_copyData(&d, &m, sims[i].start);
      for (int j = 0; j < a1::kNumJoints; ++j) {
        const double target = a1::kDefaultJointPos[j] + a1::kActionScale * Uniform(rng, -1.0, 1.0);
        d.ctrl[index.actuator[j]] =
            MotorTorque(a1::kKp, a1::kKd, target, 0.0, d.qpos[index.qpos[j]], d.qvel[index.qvel[j]], 0.0);
      }
      for (int k = 0; k < a1::kDecimation; ++k) {
        mj_step(&m, &d);
        contacts += d.ncon;
      }
      steps += a1::kDecimation;
    }
  }
  steps_out += steps;
  contacts_out += contacts;
}

// Runs the bare loop over `sims` shared out as the VecEnv shares its envs.
void TimeCeiling(const std::vector<BareSim>& sims, const A1ModelIndex& index, int threads,
                 double seconds, uint64_t seed, Tally& tally) {
  std::atomic<long> steps{0}, contacts{0};
  std::vector<std::thread> pool;
  const int n = static_cast<int>(sims.size());
  const Clock::time_point start = Clock::now();
  for (int t = 0; t < threads; ++t) {
    pool.emplace_back(BareStepLoop, std::cref(sims), n * t / threads, n * (t + 1) / threads,
                      std::cref(index), seconds, StreamSeed(seed, t), std::ref(steps), std::ref(contacts));
  }
  for (std::thread& t : pool) t.join();
  tally.seconds += Seconds(start);
  tally.steps += static_cast<double>(steps.load());
  tally.contacts += static_cast<double>(contacts.load());
}

std::vector<BareSim> SameSimulations(VecEnv& vec) {
  std::vector<BareSim> sims;
  for (int i = 0; i < vec.num_envs(); ++i) sims.push_back({&vec.env(i).model(), &vec.env(i).data()});
  return sims;
}

}  // namespace

double MeasurePhysicsCeiling(VecEnv& vec, double seconds, uint64_t seed) {
  Tally tally;
  TimeCeiling(SameSimulations(vec), vec.env(0).index(), vec.num_threads(), seconds, seed, tally);
  return tally.steps / tally.seconds / a1::kDecimation;
}

nlohmann::json RunSimBenchmark(const SimBenchOptions& options) {
  const EnvConfig config =
      options.config.empty() ? EnvConfig{} : LoadConfigSection<EnvConfig>(options.config, "env");
  const int threads = ResolveThreadCount(options.num_threads);
  VecEnv vec(config, options.num_envs, options.seed, threads);

  // Ceiling 1: the same simulations as the VecEnv (each env's own randomised model and state).
  const std::vector<BareSim> same_sims = SameSimulations(vec);
  // Ceiling 2: one nominal standing A1 per thread, all in cache: the cost of mj_step itself.
  EnvConfig nominal = config;
  nominal.randomization.DisableAll();
  nominal.reset.base_velocity = 0.0;
  nominal.reset.joint_pos_scale = {1.0, 1.0};
  const MjModelPtr model = LoadMjModel(config.model);
  const Env stand(*model, nominal, options.seed);
  const std::vector<BareSim> hot_sims(threads, BareSim{&stand.model(), &stand.data()});

  Rng rng(options.seed);
  Tally env, ceiling, hot;
  TimeVecEnv(vec, 0.2, rng, env);  // warm-up
  env = Tally{};
  // Alternate the sides so that drift on a shared machine hits all alike.
  constexpr int kRounds = 3;
  const double slice = options.seconds / kRounds;
  for (int round = 0; round < kRounds; ++round) {
    TimeCeiling(same_sims, stand.index(), threads, slice, options.seed + round, ceiling);
    TimeVecEnv(vec, slice, rng, env);
    TimeCeiling(hot_sims, stand.index(), threads, slice / 2, options.seed + round, hot);
  }

  const double env_rate = env.steps / env.seconds;
  const double ceiling_rate = ceiling.steps / ceiling.seconds / a1::kDecimation;
  const double hot_mj_step_rate = hot.steps / hot.seconds;
  const double hot_rate = hot_mj_step_rate / a1::kDecimation;
  return {
      {"benchmark", "sim"},
      {"machine", MachineDescription()},
      {"mujoco_version", mj_versionString()},
      {"num_envs", options.num_envs},
      {"threads", threads},
      {"seconds", options.seconds},
      {"env_steps_per_s", env_rate},
      {"physics_ceiling_steps_per_s", ceiling_rate},
      {"ratio", env_rate / ceiling_rate},
      {"single_model_ceiling_steps_per_s", hot_rate},
      {"ratio_vs_single_model", env_rate / hot_rate},
      {"mj_step_us", 1e6 * threads / hot_mj_step_rate},
      {"mean_contacts", ceiling.contacts / ceiling.steps},
  };
}

}  // namespace flsd
