// Controller in lockstep with the real MuJoCo A1 and the shipped library: modes, transitions
// through Stand, skill durations, latched stops, fall detection, backend faults, and a control
// tick that allocates nothing.

#include "server/controller.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <set>
#include <utility>
#include <vector>

#include "skills/runtime/safetensors.h"
#include "tests/common/test_support.h"
#include "tests/common/skill_choice.h"
#include "tests/server/server_fixture.h"

#include "tests/common/malloc_counter.h"

namespace flsd {
namespace {

using ::testing::HasSubstr;
using Kind = ControlRequest::Kind;

class ControllerTest : public testutil::ControllerFixture {
 protected:
  static ControlRequest VelocityRequest(double vx, double wz, double duration, bool navigate = false) {
    ControlRequest r = Request(Kind::kVelocity, 0, duration);
    r.velocity = {vx, 0.0, wz};
    r.navigate = navigate;
    return r;
  }
  // The idle robot rolled 1.6 rad about x: a hazard that forbids stiffening it.
  void RollOntoItsSide() {
    mjData& d = backend_.env().data();
    const int q = backend_.env().index().root_qpos;
    d.qpos[q + 3] = std::cos(0.8);
    d.qpos[q + 4] = std::sin(0.8);
    backend_.env().SyncState();
  }
};

double MaxJointError(const RobotState& s) {
  double worst = 0.0;
  for (int j = 0; j < a1::kNumJoints; ++j) worst = std::max(worst, std::abs(s.joint_position[j] - a1::kDefaultJointPos[j]));
  return worst;
}

TEST_F(ControllerTest, IdleDampsTheRobotDownToTheFloor) {
  EXPECT_EQ(controller_.status().mode, Mode::kIdle);
  EXPECT_EQ(RunFor(2.0, Mode::kIdle), 100);
  EXPECT_LT(controller_.status().state.base_position.z(), 0.15);
  EXPECT_EQ(controller_.status().faults, 0u);  // lying down while idle is no fault
}

TEST_F(ControllerTest, StandRisesFromTheFloorToTheDefaultPose) {
  RunFor(2.0);
  StandUp();
  const ControllerStatus s = controller_.status();
  EXPECT_GT(s.state.base_position.z(), 0.22);
  // Kp 40 (twice the training gains) holds 12.8 kg sagging 0.12 rad.
  EXPECT_LT(MaxJointError(s.state), 0.2);
  EXPECT_EQ(s.faults, 0u);
}

TEST_F(ControllerTest, SkillRunsForItsDurationThenStands) {
  StandUp();
  ASSERT_TRUE(controller_.Submit(Request(Kind::kSkill, testutil::CalmestStraightSkill(controller_.library()), 1.0)));
  // Standing already, it still settles in the default pose for half a second first.
  const int skill_ticks = RunFor(3.0, Mode::kSkill);
  const ControllerStatus s = controller_.status();
  EXPECT_EQ(skill_ticks, 50);
  EXPECT_EQ(s.mode, Mode::kStand);
  EXPECT_EQ(s.task.state, TaskState::kSucceeded);
  EXPECT_EQ(s.task.request_id, 42u);
  EXPECT_STREQ(s.task.client_id.data(), "test-client");
  EXPECT_STREQ(s.task.call.data(), "execute_skill");
  EXPECT_EQ(s.task.remaining, 0.0);
}

TEST_F(ControllerTest, ASkillFromIdleStandsUpFirstAndCountsTheStandInItsRemainingTime) {
  RunFor(1.0);
  ASSERT_TRUE(controller_.Submit(Request(Kind::kSkill, 1, 2.0)));
  controller_.Tick();
  const ControllerStatus s = controller_.status();
  EXPECT_EQ(s.mode, Mode::kStand);
  EXPECT_EQ(s.task.state, TaskState::kRunning);
  EXPECT_GT(s.task.remaining, 2.5);  // 2 s of skill after rising and settling
  EXPECT_EQ(RunFor(6.0, Mode::kSkill), 100);
  EXPECT_EQ(controller_.status().task.state, TaskState::kSucceeded);
}

TEST_F(ControllerTest, DampLatchesUntilClearedAndIgnoresStandsAndSkillsMeanwhile) {
  StandUp();
  ASSERT_TRUE(controller_.Submit(Request(Kind::kSkill, 0, 5.0)));
  RunFor(1.0);
  ControlRequest damp = Request(Kind::kDamp);
  SetText(damp.reason, "emergency stop from test");
  ASSERT_TRUE(controller_.Submit(damp));
  controller_.Tick();
  ControllerStatus s = controller_.status();
  EXPECT_EQ(s.mode, Mode::kDamp);
  EXPECT_EQ(s.faults & kFaultStop, kFaultStop);
  EXPECT_EQ(s.task.state, TaskState::kCancelled);
  EXPECT_STREQ(s.task.message.data(), "emergency stop from test");

  ASSERT_TRUE(controller_.Submit(Request(Kind::kSkill, 0, 5.0)));
  RunFor(0.5);
  EXPECT_EQ(controller_.status().mode, Mode::kDamp);

  // Nor does a stand lift it: only a clear, after which the robot lies damped until it stands.
  ASSERT_TRUE(controller_.Submit(Request(Kind::kStand)));
  RunFor(0.5);
  EXPECT_EQ(controller_.status().mode, Mode::kDamp);
  EXPECT_STREQ(controller_.status().stop.client.data(), "test-client");
  ControlRequest other = Request(Kind::kClearStop);  // not the presser's, within the hold time: refused
  SetText(other.client_id, "other-client");
  const uint64_t refused = controller_.Submit(other);
  controller_.Tick();
  EXPECT_EQ(controller_.status().mode, Mode::kDamp);
  ApplyRefusal refusal;
  EXPECT_EQ(controller_.OutcomeOf(refused, &refusal), Controller::Outcome::kRefused);
  EXPECT_EQ(refusal.latched & kFaultStop, kFaultStop);
  ControlRequest clear = Request(Kind::kClearStop);
  ASSERT_TRUE(controller_.Submit(clear));
  controller_.Tick();
  EXPECT_EQ(controller_.status().mode, Mode::kIdle);
  EXPECT_EQ(controller_.status().faults, 0u);
  StandUp();
}

TEST_F(ControllerTest, ASkillThatRacesADampEndsAsASafetyStopInsteadOfVanishing) {
  StandUp();
  controller_.SubmitUrgent(Request(Kind::kDamp));
  controller_.Tick();
  ASSERT_TRUE(controller_.Submit(Request(Kind::kSkill, 0, 5.0)));
  controller_.Tick();
  const ControllerStatus s = controller_.status();
  EXPECT_EQ(s.mode, Mode::kDamp);
  EXPECT_EQ(s.task.state, TaskState::kSafetyStop);
  EXPECT_EQ(s.task.request_id, 42u);
  EXPECT_THAT(s.task.message.data(), HasSubstr("latched before the skill could start"));
}

TEST_F(ControllerTest, ASkillIsNotStartedOnARobotLyingOnItsSide) {
  RollOntoItsSide();
  controller_.Tick();
  ASSERT_TRUE(controller_.Submit(Request(Kind::kSkill, 0, 2.0)));
  controller_.Tick();
  const ControllerStatus s = controller_.status();
  EXPECT_EQ(s.mode, Mode::kIdle);
  EXPECT_EQ(s.task.state, TaskState::kSafetyStop);
  EXPECT_THAT(s.task.message.data(), HasSubstr("tilt"));
  EXPECT_NE(s.hazards & kFaultTilt, 0u);
  // The tick that resets it reports the reset robot's hazards, not the fallen one's: a client that
  // sees it upright at the origin may start it at once.
  ASSERT_TRUE(controller_.Submit(Request(Kind::kReset)));
  controller_.Tick();
  EXPECT_EQ(controller_.status().hazards, 0u);
}

TEST_F(ControllerTest, UrgentStopsOverrideAFullQueue) {
  StandUp();
  while (controller_.Submit(Request(Kind::kStand))) {
  }
  controller_.SubmitUrgent(Request(Kind::kDamp));
  controller_.Tick();
  EXPECT_EQ(controller_.status().mode, Mode::kDamp);  // applied after the queue's stands
}

TEST_F(ControllerTest, StandIsIgnoredWhileTheBackendIsFaulted) {
  StandUp();
  backend_.env().data().qvel[0] = NAN;
  controller_.Tick();
  controller_.Tick();
  ASSERT_EQ(controller_.status().mode, Mode::kDamp);
  EXPECT_NE(controller_.status().hazards & kFaultBackend, 0u);
  ASSERT_TRUE(controller_.Submit(Request(Kind::kStand)));
  controller_.Tick();
  EXPECT_EQ(controller_.status().mode, Mode::kDamp);
  EXPECT_NE(controller_.status().faults, 0u);
}

TEST_F(ControllerTest, AFallDuringASkillTripsToDampingAndEndsTheTask) {
  StandUp();
  ASSERT_TRUE(controller_.Submit(Request(Kind::kSkill, 0, 5.0)));
  RunFor(1.0);
  // Knock the robot over: roll it 1.5 rad about its x axis.
  mjData& d = backend_.env().data();
  const int q = backend_.env().index().root_qpos;
  const Eigen::Quaterniond rolled(Eigen::AngleAxisd(1.5, Eigen::Vector3d::UnitX()));
  d.qpos[q + 3] = rolled.w();
  d.qpos[q + 4] = rolled.x();
  d.qpos[q + 5] = rolled.y();
  d.qpos[q + 6] = rolled.z();
  backend_.env().SyncState();
  controller_.Tick();
  const ControllerStatus s = controller_.status();
  EXPECT_EQ(s.mode, Mode::kDamp);
  EXPECT_EQ(s.faults & kFaultTilt, kFaultTilt);
  EXPECT_EQ(s.task.state, TaskState::kSafetyStop);
  EXPECT_THAT(s.task.message.data(), HasSubstr("tilt"));
  EXPECT_THAT(s.fault_message.data(), HasSubstr("tilt"));
  EXPECT_EQ(s.safety_trips, 1u);
}

TEST_F(ControllerTest, AnUnstableSimulationIsABackendFaultThatResetClears) {
  StandUp();
  backend_.env().data().qvel[0] = NAN;
  controller_.Tick();  // the backend finds the fault while it steps...
  controller_.Tick();  // ...and the supervisor reads it at the start of the next tick
  ControllerStatus s = controller_.status();
  EXPECT_EQ(s.mode, Mode::kDamp);
  EXPECT_EQ(s.faults & kFaultBackend, kFaultBackend);
  EXPECT_THAT(backend_.Fault(), HasSubstr("unstable simulation"));

  ASSERT_TRUE(controller_.Submit(Request(Kind::kReset)));
  RunFor(1.0);
  s = controller_.status();
  EXPECT_EQ(s.mode, Mode::kStand);
  EXPECT_EQ(s.faults, 0u);
  EXPECT_GT(s.state.base_position.z(), 0.22);
}

TEST_F(ControllerTest, StopEndsASkillEarlyAndStands) {
  StandUp();
  ASSERT_TRUE(controller_.Submit(Request(Kind::kSkill, 3, 10.0)));
  RunFor(1.5);
  ASSERT_EQ(controller_.status().mode, Mode::kSkill);
  ControlRequest stop = Request(Kind::kStop);
  stop.stop_state = TaskState::kLeaseLost;
  SetText(stop.reason, "lease lapsed");
  ASSERT_TRUE(controller_.Submit(stop));
  controller_.Tick();
  const ControllerStatus s = controller_.status();
  EXPECT_EQ(s.mode, Mode::kStand);
  EXPECT_EQ(s.task.state, TaskState::kLeaseLost);
  EXPECT_STREQ(s.task.message.data(), "lease lapsed");
}

TEST_F(ControllerTest, TheQueueRefusesRequestsBeyondItsSize) {
  int accepted = 0;
  while (controller_.Submit(Request(Kind::kStand)) && accepted < 1000) ++accepted;
  EXPECT_EQ(accepted, 16);
  controller_.Tick();  // drains it
  EXPECT_TRUE(controller_.Submit(Request(Kind::kStand)));
}

TEST_F(ControllerTest, TheControlTickAllocatesNothing) {
  StandUp();
  ASSERT_TRUE(controller_.Submit(Request(Kind::kSkill, 0, 1.5)));
  RunFor(1.0);  // into the skill
  ASSERT_EQ(controller_.status().mode, Mode::kSkill);
  EXPECT_EQ(testutil::CountMallocs([&] {
              for (int i = 0; i < 100; ++i) controller_.Tick();  // skill, then stand again
            }),
            0);
  EXPECT_EQ(controller_.status().mode, Mode::kStand);
}

// What the request side accepted but a tick refuses is recorded under its ticket, for the reply
// waiting for it, and two presses in one tick are both kept; the tick allocates nothing for either.
TEST_F(ControllerTest, ATickRecordsWhatItRefusesAndBothPressesWithoutAllocating) {
  RollOntoItsSide();
  controller_.Tick();
  const uint64_t stand = controller_.Submit(Request(Kind::kStand));
  ControlRequest a = Request(Kind::kDamp), b = Request(Kind::kDamp);
  SetText(a.client_id, "a");
  SetText(b.client_id, "b");
  const uint64_t damp = controller_.SubmitUrgent(a);
  controller_.SubmitUrgent(b);
  EXPECT_EQ(testutil::CountMallocs([&] { controller_.Tick(); }), 0);
  ApplyRefusal refusal;
  ASSERT_EQ(controller_.OutcomeOf(stand, &refusal), Controller::Outcome::kRefused);
  EXPECT_NE(refusal.hazards & kFaultTilt, 0u);
  EXPECT_THAT(refusal.reason.data(), HasSubstr("tilt"));
  EXPECT_EQ(controller_.OutcomeOf(damp), Controller::Outcome::kApplied);
  const StopPresses stop = controller_.status().stop;
  EXPECT_STREQ(stop.client.data(), "b");
  EXPECT_STREQ(stop.other_client.data(), "a");
  // Neither may clear it at once: the other pressed too. Any client may after the hold time.
  const double hold = config_.safety.stop_hold_time;
  EXPECT_EQ(stop.ClearableAt("a", hold), stop.time + hold);
  EXPECT_EQ(stop.ClearableAt("b", hold), stop.other_time + hold);
  ControlRequest clear = Request(Kind::kClearStop);
  SetText(clear.client_id, "b");
  const uint64_t early = controller_.Submit(clear);
  const uint64_t reset = controller_.Submit(Request(Kind::kReset));
  controller_.Tick();
  EXPECT_EQ(controller_.OutcomeOf(early), Controller::Outcome::kRefused);
  ASSERT_EQ(controller_.OutcomeOf(reset, &refusal), Controller::Outcome::kRefused);
  EXPECT_EQ(refusal.latched & kFaultStop, kFaultStop);
  RunFor(hold);
  const uint64_t late = controller_.Submit(clear);
  controller_.Tick();
  EXPECT_EQ(controller_.OutcomeOf(late), Controller::Outcome::kApplied);
  EXPECT_EQ(controller_.status().mode, Mode::kIdle);
  // A flood of refused requests, the queue full every tick, leaves a refusal on record for seconds
  // (a reply reads it a tick or two later); after 2048 later tickets it is no longer known.
  controller_.SubmitUrgent(a);  // stands are refused while it is latched
  controller_.Tick();
  const uint64_t first = controller_.Submit(Request(Kind::kStand));
  for (int tick = 0; tick < 100; ++tick) {
    while (controller_.Submit(Request(Kind::kStand))) {
    }
    controller_.Tick();
  }
  EXPECT_EQ(controller_.OutcomeOf(first), Controller::Outcome::kRefused);  // 1599 tickets later
  for (int tick = 0; tick < 30; ++tick) {
    while (controller_.Submit(Request(Kind::kStand))) {
    }
    controller_.Tick();
  }
  EXPECT_EQ(controller_.OutcomeOf(first), Controller::Outcome::kUnknown);  // 2079 later
}

// The selector runs the skills each tick: the published skill is the selector's choice, and the
// task ends after its duration with the robot standing.
TEST_F(ControllerTest, VelocityModeRunsTheSelectorsSkillsForItsDuration) {
  ASSERT_TRUE(controller_.selector());
  StandUp();
  // Standing still, so that the test is of the controller, not of how well the selector walks.
  ASSERT_TRUE(controller_.Submit(VelocityRequest(0.0, 0.0, 2.0)));
  std::set<int> chosen;
  int in_velocity = 0;
  for (int i = 0; i < 200; ++i) {
    controller_.Tick();
    const ControllerStatus s = controller_.status();
    if (s.mode == Mode::kVelocity) {
      ++in_velocity;
      ASSERT_GE(s.skill, 0);
      ASSERT_LT(s.skill, controller_.library().num_skills());
      chosen.insert(s.skill);
    }
  }
  EXPECT_NEAR(in_velocity, 100, 2);  // 2 s at 50 Hz
  EXPECT_FALSE(chosen.empty());
  EXPECT_EQ(controller_.status().task.state, TaskState::kSucceeded);
  EXPECT_THAT(controller_.status().task.message.data(), HasSubstr("velocity tracked"));
  EXPECT_EQ(controller_.status().mode, Mode::kStand);
}

// A new velocity task for another command chooses its skill at once (the last task's 1 s hold and the
// time-sharing account do not carry over), the same command streamed keeps them, and a command
// update sent while the robot still stands up for its task is applied, not dropped.
TEST_F(ControllerTest, ANewCommandChoosesAfreshAStreamedOneKeepsTheAccountAndStandUpUpdatesApply) {
  const auto moves_back = [&] {
    return controller_.library().skills()[controller_.status().skill].mean_linear_velocity.x() < -0.2;
  };
  ASSERT_TRUE(controller_.Submit(VelocityRequest(0.5, 0.0, 10.0)));
  controller_.Tick();
  ASSERT_EQ(controller_.status().mode, Mode::kStand);  // rising from the floor first
  ControlRequest update = Request(Kind::kVelocityUpdate);
  update.velocity = {-0.5, 0.0, 0.0};
  SetText(update.reason, "backward after all");
  ASSERT_TRUE(controller_.Submit(update));
  controller_.Tick();
  EXPECT_THAT(controller_.status().task.message.data(), HasSubstr("backward after all"));
  for (int i = 0; i < 500 && controller_.status().mode != Mode::kVelocity; ++i) controller_.Tick();
  ASSERT_EQ(controller_.status().mode, Mode::kVelocity);
  EXPECT_TRUE(moves_back()) << "skill " << controller_.status().skill;

  RunFor(0.2);  // well inside the 1 s hold
  ASSERT_TRUE(controller_.Submit(VelocityRequest(0.5, 0.0, 10.0)));
  controller_.Tick();
  ASSERT_EQ(controller_.status().mode, Mode::kVelocity);
  EXPECT_GT(controller_.library().skills()[controller_.status().skill].mean_linear_velocity.x(), 0.2)
      << "skill " << controller_.status().skill;

  // The same command sent again every 0.5 s (a streaming client) keeps the time-sharing account,
  // so the skills still alternate; started afresh each time, the account would pick one skill.
  std::set<int> chosen;
  for (int n = 0; n < 12; ++n) {
    ASSERT_TRUE(controller_.Submit(VelocityRequest(0.5, 0.0, 10.0)));
    for (int t = 0; t < 25; ++t) {
      controller_.Tick();
      ASSERT_EQ(controller_.status().mode, Mode::kVelocity);
      chosen.insert(controller_.status().skill);
    }
  }
  EXPECT_GE(chosen.size(), 2u);
}

// The navigator's steering and its ending apply only to the navigation they belong to.
TEST_F(ControllerTest, UpdatesAndStopsForAnotherTaskAreIgnored) {
  StandUp();
  ASSERT_TRUE(controller_.Submit(VelocityRequest(0.0, 0.0, 10.0, /*navigate=*/true)));
  RunFor(1.0);
  ASSERT_EQ(controller_.status().mode, Mode::kNavigate);
  ControlRequest update = Request(Kind::kVelocityUpdate);
  update.request_id = 7;  // not the running task's (42)
  SetText(update.reason, "stale");
  ControlRequest stop = Request(Kind::kStop);
  stop.request_id = 7;
  stop.scope = ControlRequest::Scope::kTask;
  stop.stop_state = TaskState::kNoPath;
  ASSERT_TRUE(controller_.Submit(update));
  ASSERT_TRUE(controller_.Submit(stop));
  controller_.Tick();
  EXPECT_EQ(controller_.status().mode, Mode::kNavigate);
  EXPECT_EQ(controller_.status().task.state, TaskState::kRunning);
  EXPECT_THAT(controller_.status().task.message.data(), ::testing::Not(HasSubstr("stale")));

  update.request_id = 42;
  SetText(update.reason, "2.0 m to go");
  ASSERT_TRUE(controller_.Submit(update));
  controller_.Tick();
  EXPECT_THAT(controller_.status().task.message.data(), HasSubstr("2.0 m to go"));
  stop.request_id = 42;
  SetText(stop.reason, "the goal is walled in");
  ASSERT_TRUE(controller_.Submit(stop));
  controller_.Tick();
  EXPECT_EQ(controller_.status().task.state, TaskState::kNoPath);
  EXPECT_EQ(controller_.status().mode, Mode::kStand);
}

// A client releasing control and starting its next task within one tick: the queue applies the
// task before the release's urgent stop, which must end only the tasks the release came after.
TEST_F(ControllerTest, AReleasesStopSparesTheTaskTheSameClientStartsAfterIt) {
  StandUp();
  ControlRequest release = Request(Kind::kStop);
  release.scope = ControlRequest::Scope::kClient;
  release.request_id = 43;
  SetText(release.reason, "control released");
  ControlRequest next = Request(Kind::kSkill, 2, 5.0);
  next.request_id = 44;
  controller_.SubmitUrgent(release);
  ASSERT_TRUE(controller_.Submit(next));
  controller_.Tick();
  EXPECT_EQ(controller_.status().task.request_id, 44u);
  EXPECT_EQ(controller_.status().task.state, TaskState::kRunning);

  release.request_id = 45;  // a release after it ends it
  controller_.SubmitUrgent(release);
  controller_.Tick();
  EXPECT_EQ(controller_.status().task.state, TaskState::kCancelled);
  EXPECT_STREQ(controller_.status().task.message.data(), "control released");
}

// The sim backend, remembering the last command the controller sent.
class RecordingBackend : public Backend {
 public:
  const char* name() const override { return "recording sim"; }
  void Send(const JointCommand& command) override {
    last = command;
    sim.Send(command);
  }
  RobotState Read() override { return sim.Read(); }
  SimBackend sim{SimBackendConfig{}};
  JointCommand last;
};

// skilld warns at start when a library cannot brake: here the shipped one with its still skills
// recorded as fallers.
TEST(ControllerBrake, ALibraryWhoseStillSkillsFellHasNoBrake) {
  SafeTensors file = ReadSafeTensors(ResolveDataPath("models/a1_flsd.safetensors"));
  nlohmann::json meta = nlohmann::json::parse(file.metadata["flsd"]);
  int still = 0;
  for (nlohmann::json& skill : meta["skills"]) {
    const auto& v = skill["mean_linear_velocity"];
    const Eigen::Vector3d velocity(v[0], v[1], skill["mean_angular_velocity"][2]);
    if (NearestSkillSelector::Distance(velocity, Eigen::Vector3d::Zero()) > Controller::kStillSpeed) continue;
    skill["fell"] = true;
    ++still;
  }
  ASSERT_GT(still, 0);
  file.metadata["flsd"] = meta.dump();
  const std::string path = testutil::UniqueTempPath("no_brake.safetensors");
  WriteSafeTensors(path, file);
  const SkillLibrary library = SkillLibrary::Load(path);
  std::remove(path.c_str());
  SimBackend backend{SimBackendConfig{}};
  EXPECT_FALSE(Controller(backend, library, ServerConfig{}).has_brake_skill());
  EXPECT_TRUE(Controller(backend, SkillLibrary::Load(ResolveDataPath("models/a1_flsd.safetensors")), ServerConfig{})
                  .has_brake_skill());
}

TEST(ControllerTargetFilter, ASkillRunsBehindTheLibrarysFilterFromThePoseItStartsIn) {
  // The shipped library, its metadata saying its skills were trained behind a 4 Hz filter.
  SafeTensors file = ReadSafeTensors(ResolveDataPath("models/a1_flsd.safetensors"));
  nlohmann::json meta = nlohmann::json::parse(file.metadata["flsd"]);
  meta["action"]["filter_hz"] = 4.0;
  file.metadata["flsd"] = meta.dump();
  const std::string path = testutil::UniqueTempPath("filtered.safetensors");
  WriteSafeTensors(path, file);
  const SkillLibrary library = SkillLibrary::Load(path);
  std::remove(path.c_str());

  RecordingBackend backend;
  Controller controller(backend, library, ServerConfig{});
  ControlRequest stand, skill;
  stand.kind = ControlRequest::Kind::kStand;
  skill.kind = ControlRequest::Kind::kSkill;
  skill.skill = 3;
  skill.duration = 1.0;
  ASSERT_TRUE(controller.Submit(stand));
  for (int i = 0; i < 150; ++i) controller.Tick();
  ASSERT_TRUE(controller.Submit(skill));
  // Tick until the skill's first command; the pose it starts from is the last state read.
  RobotState start;
  while (controller.status().mode != Mode::kSkill) {
    start = backend.sim.Read();
    controller.Tick();
  }
  // The policy's own first action, as the controller computes it.
  std::vector<float> motion(kMotionObsSize), action(kActionSize);
  const std::vector<float> zero(kActionSize, 0.0f);
  BuildMotionObservation(start, motion.data());
  PolicyRunner(library).Act(motion.data(), zero.data(), 3, action.data());
  const a1::JointArray<double> unfiltered = JointTargetsFromAction(action.data());
  const double g = 1.0 - std::exp(-2.0 * M_PI * 4.0 * a1::kControlDt);
  double largest_step = 0.0;
  for (int j = 0; j < a1::kNumJoints; ++j) {
    const double expected = std::clamp(start.joint_position[j] + g * (unfiltered[j] - start.joint_position[j]),
                                       a1::JointMin(j), a1::JointMax(j));
    EXPECT_NEAR(backend.last.position[j], expected, 1e-9) << a1::kJointNames[j];
    largest_step = std::max(largest_step, std::abs(unfiltered[j] - start.joint_position[j]));
  }
  EXPECT_GT(largest_step, 0.05);  // the check means something: the policy asked for a move
}

TEST_F(ControllerTest, TheVelocityTickAllocatesNothing) {
  StandUp();
  ASSERT_TRUE(controller_.Submit(VelocityRequest(-0.5, 0.3, 1.5)));
  RunFor(1.0);
  ASSERT_EQ(controller_.status().mode, Mode::kVelocity);
  EXPECT_EQ(testutil::CountMallocs([&] {
              for (int i = 0; i < 100; ++i) controller_.Tick();
            }),
            0);
}


// Skills back to back, without a reset between them, as a real robot must run them: each starts
// only once the robot stands within config.stand_check (a stand left tilted or crouched by the
// skill before is recovered by lying down and standing up again), and none falls.
TEST_F(ControllerTest, SkillsRunBackToBackOnlyFromAVerifiedStand) {
  std::vector<std::pair<double, int>> fastest;  // as make demo picks them
  for (const SkillDescriptor& d : controller_.library().skills()) {
    fastest.emplace_back(std::hypot(d.mean_linear_velocity[0], d.mean_linear_velocity[1]) +
                             0.3 * std::abs(d.mean_angular_velocity[2]),
                         d.id);
  }
  std::sort(fastest.rbegin(), fastest.rend());
  StandUp();
  const StandCheckConfig& check = config_.stand_check;
  for (int i = 0; i < 4; ++i) {
    const int k = fastest[i].second;
    ASSERT_TRUE(controller_.Submit(Request(Kind::kSkill, k, 4.0)));
    controller_.Tick();
    for (int t = 0; t < 1000 && controller_.status().mode == Mode::kStand; ++t) controller_.Tick();
    ControllerStatus s = controller_.status();
    ASSERT_EQ(s.mode, Mode::kSkill) << "skill " << k << ": " << s.task.message.data();
    EXPECT_LE(TiltOf(s.state), check.max_tilt) << k;
    EXPECT_GE(s.state.base_position.z(), check.min_base_height) << k;
    EXPECT_LE(MaxJointError(s.state), check.max_joint_error + 0.05) << k;  // one policy tick in
    for (int t = 0; t < 300 && s.task.state == TaskState::kRunning; ++t) {
      controller_.Tick();
      s = controller_.status();
    }
    EXPECT_EQ(s.task.state, TaskState::kSucceeded) << "skill " << k << ": " << s.task.message.data();
    ASSERT_EQ(s.faults, 0u) << "skill " << k << ": " << s.fault_message.data();
  }
}

// A robot that cannot be brought to a verified stand lies down and stands up again, and then has
// its skill refused with the reason, rather than started from wherever it is.
TEST(ControllerStandCheck, ARobotThatDoesNotStandHasItsSkillEndedWithTheReason) {
  ServerConfig config;
  config.stand_check.max_joint_error = 0.01;  // no robot stands this exactly
  config.stand_check.max_recoveries = 1;
  SimBackend backend{SimBackendConfig{}};
  Controller controller(backend, testutil::ShippedLibrary(), config);
  ControlRequest skill;
  skill.kind = ControlRequest::Kind::kSkill;
  skill.skill = 0;
  skill.duration = 2.0;
  ASSERT_TRUE(controller.Submit(skill));
  double lowest = HUGE_VAL;  // once it has stood
  bool stood = false;
  for (int t = 0; t < 1000 && controller.status().task.state != TaskState::kSafetyStop; ++t) {
    controller.Tick();
    const ControllerStatus s = controller.status();
    ASSERT_NE(s.mode, Mode::kSkill);
    stood |= s.state.base_position.z() > 0.22;
    if (stood) lowest = std::min(lowest, s.state.base_position.z());
  }
  const ControllerStatus s = controller.status();
  EXPECT_EQ(s.task.state, TaskState::kSafetyStop);
  EXPECT_THAT(s.task.message.data(), HasSubstr("not standing after 1 lie-down and stand-up recoveries ("));
  EXPECT_THAT(s.task.message.data(), HasSubstr("off the stand > 0.01"));
  EXPECT_LT(lowest, 0.1);  // it lay down once, between its two stands
  EXPECT_EQ(s.mode, Mode::kStand);
  EXPECT_EQ(s.faults, 0u);
}

// Every skill of the shipped library that skilld runs (one that fell in neither of the library's
// evaluations), each started from the stand the one before it left, ends where the controller
// brakes it and stands the robot up again without a fault or a lie-down recovery, crouches and
// fast turns included. A user runs skills in any order.
TEST_F(ControllerTest, EverySkillSkilldRunsEndsWhereTheRobotCanStandAgain) {
  StandUp();
  int run = 0, before = -1;
  for (const SkillDescriptor& d : controller_.library().skills()) {
    if (!WhyUndependable(d, config_.safety.min_skill_survival).empty()) continue;
    ++run;
    ASSERT_TRUE(controller_.Submit(Request(Kind::kSkill, d.id, 4.0)));
    ControllerStatus s = controller_.status();
    int standing = 0;  // braking the skill before, then standing until this one starts
    for (int t = 0; t < 1000 && (t == 0 || s.task.state == TaskState::kRunning); ++t) {
      controller_.Tick();
      s = controller_.status();
      standing += s.mode == Mode::kStand;
    }
    EXPECT_EQ(s.task.state, TaskState::kSucceeded) << "skill " << d.id << ": " << s.task.message.data();
    ASSERT_EQ(s.faults, 0u) << "skill " << d.id << ": " << s.fault_message.data();
    // A recovery alone takes longer: stand_check.timeout, then lying down and standing up.
    if (before >= 0) {
      EXPECT_LE(standing * a1::kControlDt, 2.5) << "from skill " << before << " to skill " << d.id;
    }
    before = d.id;
  }
  EXPECT_GE(run, 10);
  RunFor(8.0);  // the stand after the last one
  const ControllerStatus s = controller_.status();
  EXPECT_EQ(s.mode, Mode::kStand);
  EXPECT_EQ(s.faults, 0u) << s.fault_message.data();
  EXPECT_LE(TiltOf(s.state), config_.stand_check.max_tilt);
  EXPECT_GE(s.state.base_position.z(), config_.stand_check.min_base_height);
}

// The stillest skill brakes what a skill leaves moving for stand_brake_time before the stand's
// targets hold the legs: the task has succeeded by then, and an emergency stop does not wait.
TEST_F(ControllerTest, ASkillIsBrakedByTheStillestSkillThenStands) {
  const SkillLibrary& library = controller_.library();
  const int turn = testutil::FastestTurningSkill(library);
  ASSERT_GE(turn, 0);
  const double zero[3] = {0.0, 0.0, 0.0};
  const int brake = NearestSkillSelector(library).Choose(zero, turn);
  const SkillDescriptor& still = library.skills()[brake];
  const Eigen::Vector3d still_velocity(still.mean_linear_velocity.x(), still.mean_linear_velocity.y(),
                                       still.mean_angular_velocity.z());
  ASSERT_LE(NearestSkillSelector::Distance(still_velocity, Eigen::Vector3d::Zero()), 0.1);
  StandUp();
  ASSERT_TRUE(controller_.Submit(Request(Kind::kSkill, turn, 2.0)));
  ControllerStatus s = controller_.status();
  for (int t = 0; t < 500 && (t == 0 || s.task.state == TaskState::kRunning); ++t) {
    controller_.Tick();
    s = controller_.status();
  }
  EXPECT_EQ(s.task.state, TaskState::kSucceeded);
  EXPECT_EQ(s.mode, Mode::kStand);
  int braking = 0;
  for (; s.skill == brake && braking < 100; ++braking) {
    controller_.Tick();
    s = controller_.status();
  }
  EXPECT_EQ(braking, std::lround(config_.stand_brake_time / a1::kControlDt));
  EXPECT_EQ(s.mode, Mode::kStand);
  EXPECT_EQ(s.skill, -1);

  // Braking again after a second turn, an emergency stop damps on the next tick.
  ASSERT_TRUE(controller_.Submit(Request(Kind::kSkill, turn, 1.0)));
  for (int t = 0; t < 500 && !(controller_.status().mode == Mode::kStand && controller_.status().skill == brake); ++t) {
    controller_.Tick();
  }
  ASSERT_EQ(controller_.status().skill, brake);
  controller_.SubmitUrgent(Request(Kind::kDamp));
  controller_.Tick();
  s = controller_.status();
  EXPECT_EQ(s.mode, Mode::kDamp);
  EXPECT_EQ(s.skill, -1);
}

// A skill asked for while the brake runs waits for the brake and the stand; with no brake time
// the stand holds the legs at once.
TEST_F(ControllerTest, ASkillAskedForWhileBrakingStartsFromTheStandAfterIt) {
  const int turn = testutil::FastestTurningSkill(controller_.library());
  StandUp();
  ASSERT_TRUE(controller_.Submit(Request(Kind::kSkill, turn, 1.0)));
  for (int t = 0; t < 500 && controller_.status().mode != Mode::kSkill; ++t) controller_.Tick();
  RunFor(1.0);
  controller_.Tick();  // the skill's time is up: braking
  const int brake = controller_.status().skill;
  ASSERT_EQ(controller_.status().mode, Mode::kStand);
  ASSERT_GE(brake, 0);
  ASSERT_TRUE(controller_.Submit(Request(Kind::kSkill, turn, 1.0)));
  controller_.Tick();
  EXPECT_EQ(controller_.status().skill, brake);  // braking on
  EXPECT_EQ(controller_.status().task.state, TaskState::kRunning);
  int standing = 0;
  for (; standing < 500 && controller_.status().mode != Mode::kSkill; ++standing) controller_.Tick();
  EXPECT_EQ(controller_.status().mode, Mode::kSkill);
  EXPECT_EQ(controller_.status().skill, turn);
  EXPECT_GT(standing, std::lround(config_.stand_brake_time / a1::kControlDt));

  ServerConfig unbraked = config_;
  unbraked.stand_brake_time = 0.0;
  SimBackend backend{SimBackendConfig{}};
  Controller controller(backend, controller_.library(), unbraked);
  controller.Submit(Request(Kind::kSkill, testutil::CalmestStraightSkill(controller_.library()), 0.5));
  for (int t = 0; t < 500 && controller.status().mode != Mode::kSkill; ++t) controller.Tick();
  for (int t = 0; t < 50 && controller.status().mode == Mode::kSkill; ++t) controller.Tick();
  EXPECT_EQ(controller.status().mode, Mode::kStand);
  EXPECT_EQ(controller.status().skill, -1);
}

}  // namespace
}  // namespace flsd
