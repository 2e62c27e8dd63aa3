#include "sim/vec_env.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "core/rng.h"
#include "robot/observation.h"
#include "tests/common/sim_printers.h"
#include "tests/common/test_support.h"

namespace flsd {
namespace {

using ::testing::HasSubstr;
using testutil::InputErrorMessage;

constexpr int kEnvs = 6;

// The batched outputs of a VecEnv run, concatenated over steps.
struct Trace {
  std::vector<float> motion_obs, position;
  std::vector<Termination> termination;
};

// Steps `vec` `steps` times with actions uniform in [-1, 1] drawn from a fixed stream.
Trace RunRandom(VecEnv& vec, int steps) {
  Rng rng(99);
  const int n = vec.num_envs();
  std::vector<float> actions(n * kActionSize);
  Trace trace;
  for (int t = 0; t < steps; ++t) {
    for (float& a : actions) a = static_cast<float>(Uniform(rng, -1.0, 1.0));
    vec.Step(actions.data());
    trace.motion_obs.insert(trace.motion_obs.end(), vec.motion_obs(),
                            vec.motion_obs() + n * kMotionObsSize);
    trace.position.insert(trace.position.end(), vec.position(), vec.position() + n * 3);
    trace.termination.insert(trace.termination.end(), vec.termination(), vec.termination() + n);
  }
  return trace;
}

std::vector<float> Row(const float* data, int i, int width) {
  return std::vector<float>(data + i * width, data + (i + 1) * width);
}

std::vector<float> MotionObsOf(const RobotState& s) {
  std::vector<float> o(kMotionObsSize);
  BuildMotionObservation(s, o.data());
  return o;
}

TEST(VecEnv, ResultsDependOnTheSeedNotTheThreadCount) {
  const EnvConfig config;  // randomisation on, so the random streams matter
  VecEnv one(config, kEnvs, 7, 1), two(config, kEnvs, 7, 2), other_seed(config, kEnvs, 8, 2);
  EXPECT_EQ(two.num_threads(), 2);
  const Trace a = RunRandom(one, 50), b = RunRandom(two, 50), c = RunRandom(other_seed, 50);
  // Bitwise: float == is exact and the runs hold no NaN.
  EXPECT_TRUE(a.motion_obs == b.motion_obs);
  EXPECT_TRUE(a.position == b.position);
  EXPECT_TRUE(a.termination == b.termination);
  EXPECT_FALSE(a.motion_obs == c.motion_obs);
}

TEST(VecEnv, RowsAreTheEnvsObservations) {
  VecEnv vec(EnvConfig{}, kEnvs, 3, 2);
  RunRandom(vec, 10);
  for (int i = 0; i < kEnvs; ++i) {
    const RobotState& s = vec.env(i).state();
    EXPECT_EQ(Row(vec.motion_obs(), i, kMotionObsSize), MotionObsOf(s)) << "env " << i;
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(vec.position()[3 * i + k], static_cast<float>(s.base_position[k]));
    }
    for (int leg = 0; leg < a1::kNumLegs; ++leg) {
      EXPECT_EQ(vec.foot_contact()[a1::kNumLegs * i + leg], s.foot_contact[leg]) << "env " << i;
    }
  }
}

// Env i of a VecEnv is Env(model, config, StreamSeed(seed, i)): a lone twin stepped alike shows
// what the row held just before the automatic reset.
TEST(VecEnv, EndedEpisodesAreResetAndTheirLastStateKept) {
  EnvConfig config;
  config.episode_steps = 5;
  constexpr uint64_t kSeed = 21;
  VecEnv vec(config, kEnvs, kSeed, 2);
  const MjModelPtr model = LoadMjModel(config.model);
  std::vector<Env> twins;
  for (int i = 0; i < kEnvs; ++i) twins.emplace_back(*model, config, StreamSeed(kSeed, i));

  const std::vector<float> zero(kEnvs * kActionSize, 0.0f);
  for (int t = 1; t <= 5; ++t) {
    vec.Step(zero.data());
    for (int i = 0; i < kEnvs; ++i) {
      const Termination ending = twins[i].Step(zero.data());
      ASSERT_EQ(vec.termination()[i], ending) << "env " << i << " step " << t;
      ASSERT_EQ(ending, t < 5 ? Termination::kNone : Termination::kTimeOut)
          << "env " << i << " step " << t;
    }
  }
  for (int i = 0; i < kEnvs; ++i) {
    const std::vector<float> last = MotionObsOf(twins[i].state());
    EXPECT_EQ(Row(vec.terminal_motion_obs(), i, kMotionObsSize), last) << "env " << i;
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(vec.terminal_position()[3 * i + k],
                static_cast<float>(twins[i].state().base_position[k]));
    }
    // The live row is a fresh episode: the twin's next reset.
    EXPECT_EQ(vec.env(i).episode_step(), 0);
    EXPECT_NE(Row(vec.motion_obs(), i, kMotionObsSize), last) << "env " << i;
    twins[i].Reset();
    EXPECT_EQ(Row(vec.motion_obs(), i, kMotionObsSize), MotionObsOf(twins[i].state()))
        << "env " << i;
  }
}

// A bad action ends only its own env's episode, which is reset; the others go on.
TEST(VecEnv, InvalidActionResetsOnlyItsEnv) {
  VecEnv vec(EnvConfig{}, kEnvs, 5, 2);
  std::vector<float> actions(kEnvs * kActionSize, 0.0f);
  vec.Step(actions.data());
  actions[2 * kActionSize + 5] = NAN;
  vec.Step(actions.data());
  for (int i = 0; i < kEnvs; ++i) {
    if (i == 2) {
      EXPECT_EQ(vec.termination()[i], Termination::kInvalidAction);
      EXPECT_EQ(vec.env(i).episode_step(), 0);
    } else {
      EXPECT_EQ(vec.termination()[i], Termination::kNone) << "env " << i;
      EXPECT_EQ(vec.env(i).episode_step(), 2) << "env " << i;
    }
  }
}

TEST(VecEnv, NeedsAtLeastOneEnv) {
  EXPECT_THAT(InputErrorMessage([] { VecEnv vec(EnvConfig{}, 0, 1, 1); }), HasSubstr("num_envs"));
}

}  // namespace
}  // namespace flsd
