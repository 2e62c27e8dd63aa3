// The typed client API against the real skilld on loopback: skills as the library has them, tasks
// waited on to their result, refusals with their status, preemption seen by the replaced task,
// and typed state.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "skills/runtime/skill_library.h"
#include "tests/common/client_skilld_fixture.h"

namespace flsd {
namespace {

using namespace std::chrono_literals;
using ::testing::HasSubstr;

class ClientApiTest : public testutil::ClientSkilldFixture {
 protected:
  // Stands the robot up and waits until it is upright in Stand.
  static void StandUp(Client& client) {
    ASSERT_TRUE(client.AcquireControl().ok());
    const Reply stand = client.Stand();
    ASSERT_TRUE(stand.ok()) << stand.Describe();
    for (uint64_t tick = 0;;) {
      const std::optional<StateReport> s = client.NextState(tick, 10s);
      ASSERT_TRUE(s) << "no state";
      if (s->mode == Mode::kStand && s->position[2] > 0.22) return;
      tick = s->tick;
    }
  }
};

TEST_F(ClientApiTest, ListSkillsReturnsTheLibrarysDescriptors) {
  StartServer();
  auto client = Connect();
  const SkillLibrary library = SkillLibrary::Load(FLSD_SOURCE_DIR "/models/a1_flsd.safetensors");
  const std::vector<SkillInfo> skills = client->ListSkills();
  ASSERT_EQ(static_cast<int>(skills.size()), library.num_skills());
  for (std::size_t k = 0; k < skills.size(); ++k) {
    const SkillDescriptor& d = library.skills()[k];
    EXPECT_EQ(skills[k].id, d.id);
    for (int a = 0; a < 3; ++a) {
      EXPECT_DOUBLE_EQ(skills[k].linear_velocity[a], d.mean_linear_velocity[a]) << "skill " << k;
      EXPECT_DOUBLE_EQ(skills[k].angular_velocity[a], d.mean_angular_velocity[a]) << "skill " << k;
    }
    EXPECT_DOUBLE_EQ(skills[k].base_height, d.mean_base_height);
    EXPECT_DOUBLE_EQ(skills[k].gait_frequency, d.gait_frequency_hz);
    // The steps before its earliest fall in either evaluation, or the whole evaluation.
    const std::optional<SkillFall> fall = EarliestFall(d);
    EXPECT_EQ(skills[k].survival_steps, fall ? fall->steps : d.survival_steps) << "skill " << k;
  }
}

TEST_F(ClientApiTest, ASkillTaskIsWaitedOnToItsResult) {
  StartServer();
  auto client = Connect();
  StandUp(*client);
  const Task task = client->ExecuteSkill(0, 1.5);
  ASSERT_TRUE(task.accepted()) << task.reply().Describe();
  EXPECT_THAT(task.reply().message, HasSubstr("skill 0 for 1.50 s accepted"));
  EXPECT_FALSE(task.Done());
  ASSERT_TRUE(task.Wait(15s)) << "still " << Name(task.Progress().state);
  const TaskReport result = task.Progress();
  EXPECT_EQ(result.state, TaskState::kSucceeded) << result.message;
  EXPECT_TRUE(task.Succeeded());
  EXPECT_EQ(result.call, "execute_skill");
  EXPECT_EQ(result.client_id, client->id());
  EXPECT_EQ(result.request_id, task.request_id());
  EXPECT_GE(result.elapsed, 1.48);  // from acceptance: the wait for a verified stand counts too
  EXPECT_NEAR(result.remaining, 0.0, 0.03);
  const std::optional<StateReport> state = client->State();
  ASSERT_TRUE(state);
  EXPECT_EQ(state->backend, "sim");
  EXPECT_EQ(state->controller, client->id());
  EXPECT_EQ(state->task.request_id, task.request_id());
}

TEST_F(ClientApiTest, RefusedCallsSayWhyAndRefusedTasksAreDoneAtOnce) {
  StartServer();
  auto client = Connect();
  const Task without_control = client->ExecuteSkill(0, 1.0);
  EXPECT_EQ(without_control.reply().status, ReplyStatus::kNotInControl);
  EXPECT_TRUE(without_control.Done());
  EXPECT_TRUE(without_control.Wait(0ms));
  EXPECT_EQ(without_control.Progress().state, TaskState::kNone);

  ASSERT_TRUE(client->AcquireControl().ok());
  const Task unknown_skill = client->ExecuteSkill(99, 1.0);
  EXPECT_EQ(unknown_skill.reply().status, ReplyStatus::kInvalidArgument);
  EXPECT_THAT(unknown_skill.reply().message, HasSubstr("skill 99 is not in [0, 15)"));
  const Task nan_velocity = client->TrackVelocity(NAN, 0.0, 0.0, 1.0);
  EXPECT_EQ(nan_velocity.reply().status, ReplyStatus::kInvalidArgument);
  EXPECT_THAT(nan_velocity.reply().message, HasSubstr("velocity must be finite"));
  const Task walled_in = client->Navigate(1.0, 0.0, "bounds: [-5, 5, -5, 5]\nrobot_radius: 0.35\ncircles: [{center: [1.0, 0.0], radius: 0.5}]\n");
  ASSERT_TRUE(walled_in.accepted()) << walled_in.reply().Describe();
  ASSERT_TRUE(walled_in.Wait(15s));
  EXPECT_EQ(walled_in.Progress().state, TaskState::kNoPath);
  EXPECT_THAT(walled_in.Progress().message, HasSubstr("goal"));

  EXPECT_TRUE(client->Reset().ok());
  ASSERT_TRUE(client->Damp().ok());
  for (uint64_t tick = 0;;) {  // the stop latches at the next tick
    const std::optional<StateReport> s = client->NextState(tick, 5s);
    ASSERT_TRUE(s) << "no state";
    if (s->mode == Mode::kDamp) break;
    tick = s->tick;
  }
  const Reply stand = client->Stand();
  EXPECT_EQ(stand.status, ReplyStatus::kSafetyStop);
  EXPECT_THAT(stand.message, HasSubstr("cannot stand: an emergency stop from " + client->id() + " is latched"));
  EXPECT_TRUE(client->ClearStop().ok());
  const Reply status = client->Status();
  EXPECT_TRUE(status.ok());
  EXPECT_THAT(status.message, HasSubstr("control " + client->id()));
  EXPECT_TRUE(client->ReleaseControl().ok());
}

TEST_F(ClientApiTest, ATaskReplacedByTheNextOneEndsAsPreempted) {
  StartServer();
  auto client = Connect();
  StandUp(*client);
  const Task first = client->TrackVelocity(0.3, 0.0, 0.0, 30.0);
  ASSERT_TRUE(first.accepted()) << first.reply().Describe();
  for (int i = 0; i < 200 && first.Progress().state != TaskState::kRunning; ++i) std::this_thread::sleep_for(20ms);
  ASSERT_EQ(first.Progress().state, TaskState::kRunning);
  const Task second = client->TrackVelocity(0.0, 0.0, 0.5, 30.0);
  ASSERT_TRUE(second.accepted()) << second.reply().Describe();
  ASSERT_TRUE(first.Wait(5s));
  EXPECT_EQ(first.Progress().state, TaskState::kPreempted);
  EXPECT_THAT(first.Progress().message, HasSubstr("replaced by track_velocity from " + client->id()));
  ASSERT_TRUE(client->Stop().ok());
  ASSERT_TRUE(second.Wait(5s));
  EXPECT_EQ(second.Progress().state, TaskState::kCancelled);
}

TEST(ClientApiNoServerTest, CallsWithoutAServerHaveNoReply) {
  testutil::UseLoopbackDds();
  Client::Options options;
  options.domain_id = testutil::TestDomainId();
  options.partition = testutil::TestPartition();
  Client client(options);
  const Reply r = client.Status(200ms);
  EXPECT_EQ(r.status, ReplyStatus::kNoReply);
  EXPECT_EQ(r.Describe(), "no reply from skilld");
  try {
    client.ListSkills(200ms);
    FAIL() << "ListSkills without a server returned";
  } catch (const CallError& e) {
    EXPECT_EQ(e.reply().status, ReplyStatus::kNoReply);
  }
  EXPECT_FALSE(client.State());
}

}  // namespace
}  // namespace flsd
