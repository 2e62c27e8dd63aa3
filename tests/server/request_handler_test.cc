// RequestHandler with injected time: the lease decides who may move the robot, bad input gets a
// reply that says what is wrong, duplicates and late requests are not executed, floods are
// dropped and counted, and a lapsed lease makes the robot stand.

#include "server/request_handler.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <climits>
#include <cmath>
#include <condition_variable>
#include <mutex>
#include <cstdio>
#include <string>

#include "core/check.h"
#include "tests/common/test_support.h"
#include "tests/common/skill_choice.h"
#include "tests/server/server_fixture.h"

namespace flsd {
namespace {

using ::testing::HasSubstr;

// A request whose strings live as long as it does.
struct TestRequest {
  std::string client, call;
  flsd_msgs_Request msg{};
  TestRequest(std::string client_id, uint64_t id, std::string call_name) : client(std::move(client_id)), call(std::move(call_name)) {
    msg.header.client_id = client.data();
    msg.header.request_id = id;
    msg.call = call.data();
    msg.map_yaml = const_cast<char*>("");
  }
};

class RequestHandlerTest : public testutil::ControllerFixture {
 protected:
  RequestHandlerTest() : handler_(controller_, config_) {}

  ReplyContent Send(const std::string& client, const std::string& call, double now = 0.0,
                    void (*edit)(flsd_msgs_Request&) = nullptr) {
    TestRequest r(client, ++ids_[client], call);
    if (edit != nullptr) edit(r.msg);
    std::optional<ReplyContent> reply = handler_.Handle(r.msg, now, kWallNow);
    EXPECT_TRUE(reply.has_value()) << call << " was dropped";
    return reply.value_or(ReplyContent{});
  }
  ReplyContent Skill(const std::string& client, int skill, double duration, double now = 0.0) {
    TestRequest r(client, ++ids_[client], "execute_skill");
    r.msg.skill = skill;
    r.msg.duration = duration;
    return handler_.Handle(r.msg, now, kWallNow).value_or(ReplyContent{});
  }

  // The reply as DdsService sends it, once a tick has applied its request.
  ReplyContent Settled(ReplyContent reply) const {
    EXPECT_GE(controller_.status().applied, reply.ticket);
    if (reply.settle) reply.settle(reply, controller_.status());
    return reply;
  }
  // Rolls the robot 1.6 rad onto its side.
  void TipOver() {
    mjData& d = backend_.env().data();
    d.qpos[backend_.env().index().root_qpos + 3] = std::cos(0.8);
    d.qpos[backend_.env().index().root_qpos + 4] = std::sin(0.8);
    backend_.env().SyncState();
  }

  static constexpr int64_t kWallNow = 1'000'000'000'000;
  RequestHandler handler_;
  std::map<std::string, uint64_t> ids_;
};

TEST_F(RequestHandlerTest, ListAndStatusNeedNoControl) {
  const ReplyContent list = Send("a", "list_skills");
  EXPECT_EQ(list.status, ReplyStatus::kOk);
  EXPECT_TRUE(list.with_skills);
  const ReplyContent status = Send("a", "status");
  EXPECT_EQ(status.status, ReplyStatus::kOk);
  EXPECT_THAT(status.message, HasSubstr("mode idle"));
  EXPECT_THAT(status.message, HasSubstr("control free"));
}

// Under a state topic (ShowStatus), a reply sent at once says what the topic showed last, not a
// tick the topic has yet to publish: a client that reads the topic after the reply never finds
// an older state there.
TEST_F(RequestHandlerTest, AReplySentAtOnceSaysWhatTheStateTopicShowedLast) {
  handler_.ShowStatus(controller_.status());
  ASSERT_EQ(Send("a", "acquire_control").status, ReplyStatus::kOk);
  ASSERT_EQ(Send("a", "stand").status, ReplyStatus::kOk);
  RunFor(3.0);
  ASSERT_EQ(controller_.status().mode, Mode::kStand);
  ASSERT_STREQ(controller_.status().controller.data(), "a");
  const std::string before = Send("b", "status").message;
  EXPECT_THAT(before, HasSubstr("mode idle"));
  EXPECT_THAT(before, HasSubstr("control free"));
  handler_.ShowStatus(controller_.status());
  const std::string after = Send("b", "status").message;
  EXPECT_THAT(after, HasSubstr("mode stand"));
  EXPECT_THAT(after, HasSubstr("control a"));
}

// A damp's reply waits for the tick that applies it, and reports the stop that tick latched: the
// trip comes before the reply, so the next reply has nothing to report.
TEST_F(RequestHandlerTest, AReplyThatWaitedReportsTheTripsOfItsTick) {
  ASSERT_EQ(Send("a", "acquire_control").status, ReplyStatus::kOk);
  const ReplyContent damp = Send("b", "damp", 0.1);
  EXPECT_EQ(damp.safety_report, "");
  controller_.Tick();
  EXPECT_THAT(Settled(damp).safety_report, HasSubstr("emergency stop"));
  EXPECT_EQ(Send("b", "status", 0.2).safety_report, "");
  EXPECT_THAT(Send("a", "status", 0.2).safety_report, HasSubstr("emergency stop"));  // each client once
  EXPECT_EQ(Send("a", "status", 0.3).safety_report, "");
}

// The status names the running skill, and in stand the still skill that brakes the last motion.
TEST_F(RequestHandlerTest, StatusNamesTheSkillRunningAndTheOneBraking) {
  const int walk = testutil::CalmestStraightSkill(controller_.library());
  ASSERT_EQ(Send("a", "acquire_control").status, ReplyStatus::kOk);
  ASSERT_EQ(Skill("a", walk, 1.0).status, ReplyStatus::kOk);
  for (int t = 0; t < 500 && controller_.status().mode != Mode::kSkill; ++t) controller_.Tick();
  EXPECT_THAT(Send("a", "status").message, HasSubstr("mode skill " + std::to_string(walk) + ","));
  for (int t = 0; t < 100 && controller_.status().mode == Mode::kSkill; ++t) controller_.Tick();
  const int brake = controller_.status().skill;
  ASSERT_GE(brake, 0);
  EXPECT_THAT(Send("a", "status").message,
              HasSubstr("mode stand (skill " + std::to_string(brake) + " braking the last motion),"));
  RunFor(config_.stand_brake_time);
  EXPECT_THAT(Send("a", "status").message, HasSubstr("mode stand, t "));
}

TEST_F(RequestHandlerTest, MotionNeedsTheLeaseAndOnlyItsHolderMoves) {
  EXPECT_THAT(Send("a", "stand").message, HasSubstr("call acquire_control first"));
  EXPECT_EQ(Send("a", "acquire_control").status, ReplyStatus::kOk);
  const ReplyContent refused = Send("b", "acquire_control", 0.1);
  EXPECT_EQ(refused.status, ReplyStatus::kNotInControl);
  EXPECT_THAT(refused.message, HasSubstr("held by a"));
  EXPECT_EQ(Skill("b", 0, 1.0, 0.2).status, ReplyStatus::kNotInControl);
  EXPECT_EQ(Send("b", "stop", 0.3).status, ReplyStatus::kNotInControl);
  EXPECT_EQ(Skill("a", 0, 1.0, 0.4).status, ReplyStatus::kOk);
}

TEST_F(RequestHandlerTest, RenewingNeverGrantsALeaseThatIsNotHeld) {
  EXPECT_EQ(Send("a", "renew_control").status, ReplyStatus::kNotInControl);
  ASSERT_EQ(Send("a", "acquire_control").status, ReplyStatus::kOk);
  EXPECT_EQ(Send("a", "renew_control", 0.9).status, ReplyStatus::kOk);
  EXPECT_EQ(Send("b", "renew_control", 1.0).status, ReplyStatus::kNotInControl);
  EXPECT_EQ(Send("a", "renew_control", 2.5).status, ReplyStatus::kNotInControl);  // lapsed at 1.9
}

TEST_F(RequestHandlerTest, AnyClientMayDamp) {
  ASSERT_EQ(Send("a", "acquire_control").status, ReplyStatus::kOk);
  EXPECT_EQ(Send("b", "damp", 0.1).status, ReplyStatus::kOk);
  controller_.Tick();
  EXPECT_EQ(controller_.status().mode, Mode::kDamp);
  const ReplyContent skill = Skill("a", 0, 1.0, 0.2);
  EXPECT_EQ(skill.status, ReplyStatus::kSafetyStop);
  EXPECT_THAT(skill.message, HasSubstr("an emergency stop from b is latched; call clear_stop"));
}

// A reply to a call that the control tick applies carries the request's ticket; DdsService sends
// it once the published status has reached it, so that the next request sees the call's effect.
// The lease changes at once.
TEST_F(RequestHandlerTest, AnOkReplyNamesTheTicketOfTheRequestItWaitsFor) {
  const auto applied_by_the_next_tick = [&](const ReplyContent& reply) {
    EXPECT_EQ(reply.status, ReplyStatus::kOk) << reply.message;
    EXPECT_GT(reply.ticket, controller_.status().applied);
    controller_.Tick();
    return controller_.status().applied >= reply.ticket;
  };
  EXPECT_TRUE(applied_by_the_next_tick(Send("a", "acquire_control")));  // the state topic names the holder
  EXPECT_EQ(Send("a", "renew_control").ticket, 0u);  // nothing for the tick to apply: answered at once
  EXPECT_EQ(Send("a", "status").ticket, 0u);
  EXPECT_TRUE(applied_by_the_next_tick(Send("a", "damp")));
  EXPECT_EQ(Send("a", "stand").status, ReplyStatus::kSafetyStop);
  EXPECT_TRUE(applied_by_the_next_tick(Send("a", "clear_stop")));
  EXPECT_TRUE(applied_by_the_next_tick(Send("a", "stand")));
  EXPECT_EQ(controller_.status().mode, Mode::kStand);
  EXPECT_TRUE(applied_by_the_next_tick(Skill("a", 0, 1.0)));
  EXPECT_EQ(controller_.status().task.state, TaskState::kRunning);
  EXPECT_TRUE(applied_by_the_next_tick(Send("a", "stop")));
  EXPECT_EQ(controller_.status().task.state, TaskState::kCancelled);
  EXPECT_TRUE(applied_by_the_next_tick(Send("a", "release_control")));
}

TEST_F(RequestHandlerTest, DampGetsThroughAQueueFloodedByTheController) {
  ASSERT_EQ(Send("a", "acquire_control").status, ReplyStatus::kOk);
  for (int i = 0; i < 40; ++i) Send("a", "stand", 0.001 * i);  // more than the queue holds
  EXPECT_EQ(Send("b", "damp", 0.1).status, ReplyStatus::kOk);
  controller_.Tick();
  EXPECT_EQ(controller_.status().mode, Mode::kDamp);
}

TEST_F(RequestHandlerTest, BadArgumentsAreRefusedWithTheReason) {
  ASSERT_EQ(Send("a", "acquire_control").status, ReplyStatus::kOk);
  const int k = controller_.library().num_skills();
  EXPECT_THAT(Skill("a", k, 1.0).message, HasSubstr("skill " + std::to_string(k) + " is not in [0, "));
  EXPECT_THAT(Skill("a", -1, 1.0).message, HasSubstr("is not in"));
  for (double bad : {0.0, -1.0, double(NAN), double(INFINITY), 1e9}) {
    const ReplyContent r = Skill("a", 0, bad);
    EXPECT_EQ(r.status, ReplyStatus::kInvalidArgument) << bad;
    EXPECT_THAT(r.message, HasSubstr("duration must be in (0, 600.00 s]")) << bad;
  }
  const ReplyContent vel = Send("a", "track_velocity", 0.0, [](flsd_msgs_Request& r) {
    r.velocity[1] = NAN;
    r.duration = 1.0;
  });
  EXPECT_EQ(vel.status, ReplyStatus::kInvalidArgument);
  EXPECT_THAT(vel.message, HasSubstr("velocity must be finite"));
  EXPECT_EQ(Send("a", "navigate", 0.0, [](flsd_msgs_Request& r) { r.goal[0] = INFINITY; }).status,
            ReplyStatus::kInvalidArgument);
}

TEST(RequestHandlerSkills, SkillsThatFellSoonInEitherEvaluationAreRefused) {
  // A library whose skill 1 fell after 9 steps in its evaluation, and whose skill 2 fell under
  // randomisation.
  SkillLibrary library = testutil::ShippedLibrary();
  ASSERT_GT(library.num_skills(), 2);
  ServerConfig config;
  SimBackend backend(config.sim);
  Controller controller(backend, library, config);
  RequestHandler handler(controller, config);
  auto call = [&](uint64_t id, const char* name, int skill) {
    TestRequest r("a", id, name);
    r.msg.skill = skill;
    r.msg.duration = 1.0;
    return *handler.Handle(r.msg, 0.0, 0);
  };
  ASSERT_EQ(call(1, "acquire_control", 0).status, ReplyStatus::kOk);
  EXPECT_EQ(call(2, "execute_skill", 1).status, ReplyStatus::kOk);  // survived 1000 steps
  // `library` is this test's own copy, so editing its descriptor in place is fine.
  auto& fallen = const_cast<SkillDescriptor&>(library.skills()[1]);
  fallen.survival_steps = 9;
  fallen.fell = true;
  const ReplyContent r = call(3, "execute_skill", 1);
  EXPECT_EQ(r.status, ReplyStatus::kNotAvailable);
  EXPECT_THAT(r.message, HasSubstr("skill 1 fell after 9 steps in the library's evaluation"));
  // Under randomisation, the real robot's case, any fall within the evaluation's 1000 steps.
  auto& pushed = const_cast<SkillDescriptor&>(library.skills()[2]);
  pushed.randomized_fell = true;
  pushed.randomized_survival_steps = 783;
  const ReplyContent late = call(4, "execute_skill", 2);
  EXPECT_EQ(late.status, ReplyStatus::kNotAvailable);
  EXPECT_THAT(late.message, HasSubstr("skill 2 fell after 783 steps in the library's randomised evaluation"));
  EXPECT_THAT(late.message, HasSubstr("(safety.min_skill_survival = 1000); it is not run"));
  pushed.randomized_survival_steps.reset();  // a fall without a count is at step 0
  EXPECT_THAT(call(5, "execute_skill", 2).message, HasSubstr("skill 2 fell after 0 steps"));
  pushed.randomized_fell = false;
  pushed.randomized_survival_steps = 1000;
  EXPECT_EQ(call(6, "execute_skill", 2).status, ReplyStatus::kOk);
}

TEST_F(RequestHandlerTest, VelocityOutsideTheTrainedRangeIsClippedAndTheReplySaysSo) {
  ASSERT_EQ(Send("a", "acquire_control").status, ReplyStatus::kOk);
  const ReplyContent r = Send("a", "track_velocity", 0.0, [](flsd_msgs_Request& m) {
    m.velocity[0] = 3.0;
    m.velocity[2] = -2.0;
    m.duration = 1.0;
  });
  ASSERT_EQ(r.status, ReplyStatus::kOk) << r.message;
  const std::array<std::array<double, 3>, 2> range = controller_.selector()->CommandRange();
  EXPECT_THAT(r.message, HasSubstr(testutil::ClippedTo("vx", range[1][0])));
  EXPECT_THAT(r.message, HasSubstr(testutil::ClippedTo("wz", range[0][2])));
  EXPECT_THAT(r.message, ::testing::Not(HasSubstr("vy clipped")));
  EXPECT_GT(RunFor(3.0, Mode::kVelocity), 0);
}

// Answers that come later, from the navigator's thread.
class LaterReplies {
 public:
  DeferredReply sink() {
    return [this](const ReplyContent& r) {
      std::lock_guard<std::mutex> lock(mutex_);
      replies_.push_back(r);
      arrived_.notify_all();
    };
  }
  // The next one, or STATUS_INTERNAL after 10 s.
  ReplyContent Next() {
    std::unique_lock<std::mutex> lock(mutex_);
    arrived_.wait_for(lock, std::chrono::seconds(10), [&] { return taken_ < replies_.size(); });
    if (taken_ < replies_.size()) return replies_[taken_++];
    ReplyContent none;
    none.status = ReplyStatus::kInternal;
    none.message = "no reply within 10 s";
    return none;
  }

 private:
  std::mutex mutex_;
  std::condition_variable arrived_;
  std::vector<ReplyContent> replies_;
  std::size_t taken_ = 0;
};

TEST_F(RequestHandlerTest, NavigateNeedsANavigatorAndAMapThatParses) {
  ASSERT_EQ(Send("a", "acquire_control").status, ReplyStatus::kOk);
  LaterReplies later;
  // The reply now, or the one the navigator sends once it has read the map.
  auto navigate = [&](RequestHandler& handler, uint64_t id, const std::string& map_yaml) {
    TestRequest r("a", id, "navigate");
    r.msg.goal[0] = 1.0;
    r.msg.map_yaml = const_cast<char*>(map_yaml.c_str());
    const std::optional<ReplyContent> now = handler.Handle(r.msg, 0.0, kWallNow, later.sink());
    return now ? *now : later.Next();
  };
  EXPECT_EQ(navigate(handler_, 10, "").status, ReplyStatus::kNotAvailable);  // no navigator here

  Navigator navigator(controller_, config_.navigation);
  RequestHandler handler(controller_, config_, &navigator);
  ASSERT_EQ(handler.Handle(TestRequest("a", 1, "acquire_control").msg, 0.0, kWallNow)->status, ReplyStatus::kOk);
  const ReplyContent no_map = navigate(handler, 2, "");
  EXPECT_EQ(no_map.status, ReplyStatus::kInvalidArgument);
  EXPECT_THAT(no_map.message, HasSubstr("no map"));
  const ReplyContent bad_map = navigate(handler, 3, "bounds: [1, 2]\n");
  EXPECT_EQ(bad_map.status, ReplyStatus::kInvalidArgument);
  EXPECT_THAT(bad_map.message, HasSubstr("the request's map"));
  // Bounds OMPL cannot sample in are refused, naming the bound.
  for (const char* bounds : {"[-.inf, .inf, -5, 5]", "[-1e300, 1e300, -5, 5]"}) {
    const ReplyContent r = navigate(handler, 4 + (bounds[2] == '1'), std::string("bounds: ") + bounds + "\n");
    EXPECT_EQ(r.status, ReplyStatus::kInvalidArgument) << bounds;
    EXPECT_THAT(r.message, HasSubstr("bounds[0] (x_min): expected a finite number within [-1000, 1000] m")) << bounds;
  }
  const ReplyContent too_big = navigate(handler, 6, std::string(Map2D::kMaxTextBytes + 1, ' '));
  EXPECT_EQ(too_big.status, ReplyStatus::kInvalidArgument);
  EXPECT_THAT(too_big.message, HasSubstr("a map may have at most 65536"));
  const ReplyContent ok = navigate(handler, 7, "bounds: [-5, 5, -5, 5]\n");
  EXPECT_EQ(ok.status, ReplyStatus::kOk) << ok.message;
  EXPECT_THAT(ok.message, HasSubstr("planning"));
}

TEST(RequestHandlerSelector, WithoutALearnedSelectorTheTimeSharingOneServesUnlessConfiguredOut) {
  // The shipped library ships no learned selector.
  const SkillLibrary& library = testutil::ShippedLibrary();
  ASSERT_FALSE(library.selector().has_value());

  SimBackend backend{SimBackendConfig{}};
  {
    // "learned" over a library without one: the velocity calls say why they are unavailable.
    ServerConfig config;
    config.selector = "learned";
    config.navigation.selector = "learned";
    Controller controller(backend, library, config);
    EXPECT_FALSE(controller.selector());
    EXPECT_FALSE(controller.selector(true));
    RequestHandler handler(controller, config);
    ASSERT_EQ(handler.Handle(TestRequest("a", 1, "acquire_control").msg, 0.0, 0)->status, ReplyStatus::kOk);
    TestRequest vel("a", 2, "track_velocity");
    vel.msg.duration = 1.0;
    const ReplyContent r = handler.Handle(vel.msg, 0.0, 0).value_or(ReplyContent{});
    EXPECT_EQ(r.status, ReplyStatus::kNotAvailable);
    EXPECT_THAT(r.message, HasSubstr("has no skill selector"));
    EXPECT_THAT(r.message, HasSubstr("the server's selector is 'learned'"));
    EXPECT_THROW(HierarchicalPolicy{library}, InputError);
  }
  // "auto", the default: the time-sharing selector for track_velocity, its commands clipped to
  // what the skills do, and the nearest-skill one for navigate.
  ServerConfig config;
  Controller controller(backend, library, config);
  ASSERT_TRUE(controller.selector());
  EXPECT_EQ(controller.selector()->kind(), SelectorKind::kTimeSharing);
  ASSERT_TRUE(controller.selector(true));
  EXPECT_EQ(controller.selector(true)->kind(), SelectorKind::kNearestSkill);
  RequestHandler handler(controller, config);
  ASSERT_EQ(handler.Handle(TestRequest("a", 1, "acquire_control").msg, 0.0, 0)->status, ReplyStatus::kOk);
  TestRequest vel("a", 2, "track_velocity");
  vel.msg.duration = 1.0;
  vel.msg.velocity[0] = 5.0;
  const ReplyContent r = handler.Handle(vel.msg, 0.0, 0).value_or(ReplyContent{});
  EXPECT_EQ(r.status, ReplyStatus::kOk) << r.message;
  EXPECT_THAT(r.message, HasSubstr("vx clipped to"));
  EXPECT_THAT(r.message, HasSubstr("the edge of the time_sharing selector's range"));
}

TEST(RequestHandlerSelector, AnUnknownSelectorInTheServerConfigIsNamed) {
  const testutil::TempFile file(".yaml", "selector: oracle\n");
  EXPECT_THAT(testutil::InputErrorMessage([&] { LoadServerConfig(file.path()); }),
              HasSubstr(file.path() + ": selector: selector 'oracle': expected learned or nearest_skill or time_sharing or auto"));
  const testutil::TempFile nearest(".yaml", "selector: nearest_skill\n");
  EXPECT_EQ(LoadServerConfig(nearest.path()).selector, "nearest_skill");
  const testutil::TempFile navigation(".yaml", "navigation:\n  selector: time-sharing\n");
  EXPECT_THAT(testutil::InputErrorMessage([&] { LoadServerConfig(navigation.path()); }),
              HasSubstr(navigation.path() + ": navigation.selector: selector 'time-sharing': expected learned or "
                                            "nearest_skill or time_sharing or auto"));
}

TEST_F(RequestHandlerTest, UnknownCallsAndBadClientIdsAreAnswered) {
  const ReplyContent r = Send("a", "fly");
  EXPECT_EQ(r.status, ReplyStatus::kUnknownCall);
  EXPECT_THAT(r.message, HasSubstr("unknown call 'fly'; known calls: list_skills"));
  EXPECT_EQ(Send("", "status").status, ReplyStatus::kInvalidArgument);
  EXPECT_THAT(Send(std::string(64, 'x'), "status").message, HasSubstr("1 to 63 characters"));
}

TEST_F(RequestHandlerTest, RepeatedOrOldRequestIdsAreNotExecuted) {
  TestRequest first("a", 10, "acquire_control");
  ASSERT_EQ(handler_.Handle(first.msg, 0.0, kWallNow)->status, ReplyStatus::kOk);
  TestRequest again("a", 10, "stand");
  const ReplyContent r = *handler_.Handle(again.msg, 0.1, kWallNow);
  EXPECT_EQ(r.status, ReplyStatus::kDuplicate);
  EXPECT_THAT(r.message, HasSubstr("request_id 10 is not above 10"));
  TestRequest older("a", 9, "stand");
  EXPECT_EQ(handler_.Handle(older.msg, 0.2, kWallNow)->status, ReplyStatus::kDuplicate);
  TestRequest other("b", 10, "status");  // ids are per client
  EXPECT_EQ(handler_.Handle(other.msg, 0.3, kWallNow)->status, ReplyStatus::kOk);
}

TEST_F(RequestHandlerTest, AForgottenClientCannotReplayItsRequests) {
  TestRequest first("e", 777, "status");
  ASSERT_EQ(handler_.Handle(first.msg, 0.0, kWallNow)->status, ReplyStatus::kOk);
  for (std::size_t i = 0; i < RequestHandler::kMaxClients + 44; ++i) {  // E is forgotten
    // Ids from a clock, as flsd::Client takes them: a newcomer's clear any forgotten client's.
    TestRequest other("other-" + std::to_string(i), 1000 + i, "status");
    ASSERT_EQ(handler_.Handle(other.msg, 0.001 * (i + 1), kWallNow)->status, ReplyStatus::kOk);
  }
  TestRequest replay("e", 777, "status");
  const ReplyContent r = *handler_.Handle(replay.msg, 1.0, kWallNow);
  EXPECT_EQ(r.status, ReplyStatus::kDuplicate);
  EXPECT_THAT(r.message, HasSubstr("request_id 777 is not above 777"));
  TestRequest next("e", 2000, "status");  // E goes on with later ids
  EXPECT_EQ(handler_.Handle(next.msg, 1.1, kWallNow)->status, ReplyStatus::kOk);
}

TEST_F(RequestHandlerTest, RequestsPastTheirDeadlineAreNotExecuted) {
  ASSERT_EQ(Send("a", "acquire_control").status, ReplyStatus::kOk);
  TestRequest late("a", 100, "stand");
  late.msg.header.deadline_ns = kWallNow - 250'000'000;
  const ReplyContent r = *handler_.Handle(late.msg, 0.1, kWallNow);
  EXPECT_EQ(r.status, ReplyStatus::kDeadlineExceeded);
  EXPECT_THAT(r.message, HasSubstr("arrived 0.25 s after its deadline"));
  controller_.Tick();
  EXPECT_EQ(controller_.status().mode, Mode::kIdle);
  // A deadline before 1970 is no time at all: refused by name, not by an overflowed lateness.
  TestRequest ancient("a", 101, "stand");
  ancient.msg.header.deadline_ns = INT64_MIN;
  const ReplyContent refused = *handler_.Handle(ancient.msg, 0.2, kWallNow);
  EXPECT_EQ(refused.status, ReplyStatus::kInvalidArgument);
  EXPECT_THAT(refused.message, HasSubstr("deadline_ns must be 0 (none) or a CLOCK_REALTIME time in ns, got -9223372036854775808"));
}

TEST_F(RequestHandlerTest, EveryRequestOfTheHolderRenewsTheLease) {
  ASSERT_EQ(Send("a", "acquire_control").status, ReplyStatus::kOk);
  for (double t = 0.5; t < 5.0; t += 0.5) {
    EXPECT_EQ(Send("a", "status", t).status, ReplyStatus::kOk);
    handler_.Poll(t + 0.49);
    EXPECT_EQ(handler_.controller_id(), "a") << t;
  }
  handler_.Poll(5.51);  // 1.01 s of silence after the last status
  EXPECT_EQ(handler_.controller_id(), "");
}

// The state topic names the lease's holder from the tick that applies a hand-over, and the OK
// reply to the call that handed it over waits for that tick (its ticket), as a stand's does.
TEST_F(RequestHandlerTest, AHandOverIsAnsweredOnceTheStatusNamesTheNewHolder) {
  const auto holder = [&] { return std::string(controller_.status().controller.data()); };
  const ReplyContent acquire = Send("a", "acquire_control");
  ASSERT_EQ(acquire.status, ReplyStatus::kOk);
  EXPECT_GT(acquire.ticket, controller_.status().applied);
  EXPECT_EQ(holder(), "");
  controller_.Tick();
  EXPECT_GE(controller_.status().applied, acquire.ticket);
  EXPECT_EQ(holder(), "a");

  const ReplyContent release = Send("a", "release_control", 0.1);
  ASSERT_EQ(release.status, ReplyStatus::kOk);
  EXPECT_GT(release.ticket, controller_.status().applied);
  EXPECT_EQ(holder(), "a");
  controller_.Tick();
  EXPECT_GE(controller_.status().applied, release.ticket);
  EXPECT_EQ(holder(), "");

  // A refused acquire changes nothing and is answered at once.
  ASSERT_EQ(Send("b", "acquire_control", 0.2).status, ReplyStatus::kOk);
  const ReplyContent refused = Send("c", "acquire_control", 0.3);
  EXPECT_EQ(refused.status, ReplyStatus::kNotInControl);
  EXPECT_EQ(refused.ticket, 0u);
  controller_.Tick();
  EXPECT_EQ(holder(), "b");
  // A lapse names nobody from its tick on.
  handler_.Poll(1.3);
  controller_.Tick();
  EXPECT_EQ(holder(), "");
}

TEST_F(RequestHandlerTest, AFloodIsDroppedAndCountedAndTheServerKeepsAnswering) {
  int answered = 0;
  for (uint64_t id = 1; id <= 1000; ++id) {
    TestRequest r("flood", id, "status");
    answered += handler_.Handle(r.msg, 5.0, kWallNow).has_value();
  }
  EXPECT_EQ(answered, config_.request_burst);
  EXPECT_EQ(handler_.dropped(), 1000u - config_.request_burst);
  EXPECT_EQ(Send("calm", "status", 5.0).status, ReplyStatus::kOk);  // others are unaffected
  TestRequest later("flood", 1001, "status");  // a second later the bucket has refilled
  EXPECT_TRUE(handler_.Handle(later.msg, 6.0, kWallNow).has_value());
}

TEST_F(RequestHandlerTest, ASilentControllerLosesTheLeaseAndTheRobotStands) {
  ASSERT_EQ(Send("a", "acquire_control").status, ReplyStatus::kOk);
  ASSERT_EQ(Skill("a", 0, 30.0, 0.0).status, ReplyStatus::kOk);
  for (int i = 0; i < 150; ++i) controller_.Tick();  // rise, settle, start the skill
  ASSERT_EQ(controller_.status().mode, Mode::kSkill);
  handler_.Poll(0.9);
  controller_.Tick();
  ASSERT_EQ(controller_.status().mode, Mode::kSkill);  // not yet lapsed
  handler_.Poll(1.01);
  controller_.Tick();
  const ControllerStatus s = controller_.status();
  EXPECT_EQ(s.mode, Mode::kStand);
  EXPECT_EQ(s.task.state, TaskState::kLeaseLost);
  EXPECT_THAT(s.task.message.data(), HasSubstr("control lease of a lapsed"));
  EXPECT_EQ(handler_.controller_id(), "");
  EXPECT_EQ(Send("b", "acquire_control", 1.1).status, ReplyStatus::kOk);
}

TEST_F(RequestHandlerTest, StandIsRefusedWhileTheRobotLiesOnItsSide) {
  ASSERT_EQ(Send("a", "acquire_control").status, ReplyStatus::kOk);
  ASSERT_EQ(Send("a", "stand").status, ReplyStatus::kOk);
  for (int i = 0; i < 150; ++i) controller_.Tick();
  mjData& d = backend_.env().data();
  d.qpos[backend_.env().index().root_qpos + 3] = std::cos(0.8);  // roll 1.6 rad
  d.qpos[backend_.env().index().root_qpos + 4] = std::sin(0.8);
  backend_.env().SyncState();
  controller_.Tick();
  ASSERT_EQ(controller_.status().mode, Mode::kDamp);
  const ReplyContent r = Send("a", "stand", 0.5);
  EXPECT_EQ(r.status, ReplyStatus::kSafetyStop);
  EXPECT_THAT(r.message, HasSubstr("cannot stand: tilt"));
  EXPECT_THAT(r.message, HasSubstr("call reset"));
  // The trip is reported once, in the first reply after it, to each client.
  EXPECT_THAT(r.safety_report, HasSubstr("tilt"));
  EXPECT_EQ(Send("a", "status", 0.6).safety_report, "");
  EXPECT_EQ(Send("a", "reset", 0.7).status, ReplyStatus::kOk);
  controller_.Tick();
  EXPECT_EQ(controller_.status().mode, Mode::kStand);
}

TEST_F(RequestHandlerTest, AnEmergencyStopLatchesUntilItsPresserOrTheHoldTimeClearsIt) {
  ASSERT_EQ(Send("a", "acquire_control").status, ReplyStatus::kOk);
  ASSERT_EQ(Send("a", "stand").status, ReplyStatus::kOk);
  RunFor(3.0);
  ASSERT_EQ(controller_.status().mode, Mode::kStand);
  EXPECT_EQ(Send("b", "damp", 0.1).status, ReplyStatus::kOk);
  controller_.Tick();
  ASSERT_EQ(controller_.status().mode, Mode::kDamp);
  // The holder's next stand does not undo it, on either side of the queue.
  const ReplyContent stand = Send("a", "stand", 0.12);
  EXPECT_EQ(stand.status, ReplyStatus::kSafetyStop);
  EXPECT_THAT(stand.message, HasSubstr("an emergency stop from b is latched; call clear_stop"));
  ControlRequest raced;
  raced.kind = ControlRequest::Kind::kStand;
  ASSERT_TRUE(controller_.Submit(raced));
  RunFor(0.5);
  EXPECT_EQ(controller_.status().mode, Mode::kDamp);
  const ReplyContent early = Send("a", "clear_stop", 0.2);
  EXPECT_EQ(early.status, ReplyStatus::kSafetyStop);
  EXPECT_THAT(early.message, HasSubstr("b may at once, any client after 10.00 s"));
  EXPECT_THAT(early.message, HasSubstr("left)"));
  // The presser may clear it at once; the robot stays damped until it is told to stand.
  EXPECT_EQ(Send("b", "clear_stop", 0.3).status, ReplyStatus::kOk);
  RunFor(0.5);
  EXPECT_EQ(controller_.status().mode, Mode::kIdle);
  EXPECT_EQ(controller_.status().faults, 0u);
  EXPECT_EQ(Send("a", "stand", 0.4).status, ReplyStatus::kOk);
  controller_.Tick();
  EXPECT_EQ(controller_.status().mode, Mode::kStand);

  // Anyone may clear it once it has been held for stop_hold_time.
  EXPECT_EQ(Send("b", "damp", 0.5).status, ReplyStatus::kOk);
  RunFor(config_.safety.stop_hold_time + 0.1);
  EXPECT_EQ(Send("a", "clear_stop", 0.6).status, ReplyStatus::kOk);
  controller_.Tick();
  EXPECT_EQ(controller_.status().mode, Mode::kIdle);
}

// Presses that reach the same tick are kept as two: neither presser may undo the other's press at
// once, each damp reply says so, and after the hold time anyone may clear the stop.
TEST_F(RequestHandlerTest, TwoPressesInOneTickAreBothKept) {
  ASSERT_EQ(Send("a", "acquire_control").status, ReplyStatus::kOk);
  const ReplyContent by_b = Send("b", "damp", 0.1);
  const ReplyContent by_a = Send("a", "damp", 0.1);
  controller_.Tick();
  ASSERT_EQ(controller_.status().mode, Mode::kDamp);
  ASSERT_GE(controller_.status().applied, std::max(by_a.ticket, by_b.ticket));
  for (const ReplyContent& reply : {Settled(by_a), Settled(by_b)}) {
    EXPECT_EQ(reply.status, ReplyStatus::kOk);
    EXPECT_THAT(reply.message, HasSubstr("emergency stops from a and from b are latched"));
  }
  const ReplyContent early_a = Send("a", "clear_stop", 0.2);
  EXPECT_EQ(early_a.status, ReplyStatus::kSafetyStop);
  EXPECT_THAT(early_a.message, HasSubstr("a may 10.00 s after b's press"));
  EXPECT_EQ(Send("b", "clear_stop", 0.3).status, ReplyStatus::kSafetyStop);
  controller_.Tick();
  EXPECT_EQ(controller_.status().mode, Mode::kDamp);
  RunFor(config_.safety.stop_hold_time);
  EXPECT_EQ(Send("c", "clear_stop", 0.4).status, ReplyStatus::kOk);
  controller_.Tick();
  EXPECT_EQ(controller_.status().mode, Mode::kIdle);
}

// The holder cannot take over a bystander's stop by pressing it too, then clear it as its own.
TEST_F(RequestHandlerTest, AHolderCannotUndoABystandersStopByPressingItToo) {
  ASSERT_EQ(Send("a", "acquire_control").status, ReplyStatus::kOk);
  ASSERT_EQ(Send("b", "damp", 0.1).status, ReplyStatus::kOk);
  controller_.Tick();
  ASSERT_EQ(Send("a", "damp", 0.2).status, ReplyStatus::kOk);
  controller_.Tick();
  const ReplyContent cleared = Send("a", "clear_stop", 0.3);
  EXPECT_EQ(cleared.status, ReplyStatus::kSafetyStop);
  EXPECT_THAT(cleared.message, HasSubstr("emergency stops from a and from b are latched"));
  controller_.Tick();
  EXPECT_EQ(controller_.status().mode, Mode::kDamp);
  // Nor may the bystander at once: the holder's press is a stop too, and it came later.
  EXPECT_EQ(Send("b", "clear_stop", 0.4).status, ReplyStatus::kSafetyStop);
}

// A stand the handler accepts but the next tick refuses, because the robot went down in between,
// is answered as the handler would have answered had it seen the hazard first; so is a skill.
TEST_F(RequestHandlerTest, ACallTheTickRefusesIsAnsweredWithTheReason) {
  ASSERT_EQ(Send("a", "acquire_control").status, ReplyStatus::kOk);
  const ReplyContent stand = Send("a", "stand", 0.1);
  ASSERT_EQ(stand.status, ReplyStatus::kOk);  // the robot lay idle, upright
  TipOver();
  controller_.Tick();
  ASSERT_GE(controller_.status().applied, stand.ticket);
  EXPECT_EQ(controller_.status().mode, Mode::kIdle);
  const ReplyContent sent = Settled(stand);
  EXPECT_EQ(sent.status, ReplyStatus::kSafetyStop);
  EXPECT_THAT(sent.message, HasSubstr("cannot stand: tilt"));
  EXPECT_THAT(sent.message, HasSubstr("call reset"));
  EXPECT_EQ(Send("a", "stand", 0.2).message, sent.message);  // as a stand asked for now is refused

  ASSERT_EQ(Send("a", "reset", 0.3).status, ReplyStatus::kOk);
  RunFor(3.0);
  ASSERT_EQ(controller_.status().mode, Mode::kStand);
  const ReplyContent skill = Skill("a", 0, 1.0, 0.4);
  ASSERT_EQ(skill.status, ReplyStatus::kOk);
  TipOver();
  controller_.Tick();
  const ReplyContent skill_sent = Settled(skill);
  EXPECT_EQ(skill_sent.status, ReplyStatus::kSafetyStop);
  EXPECT_THAT(skill_sent.message, HasSubstr("tilt"));
  EXPECT_EQ(controller_.status().task.state, TaskState::kSafetyStop);  // the state topic says so too
}

TEST_F(RequestHandlerTest, ReleasingControlStopsOnlyTheReleasersTask) {
  ASSERT_EQ(Send("x", "acquire_control").status, ReplyStatus::kOk);
  ASSERT_EQ(Skill("x", 0, 30.0).status, ReplyStatus::kOk);
  RunFor(3.0);  // control time; the handler's clock stands still
  ASSERT_EQ(controller_.status().mode, Mode::kSkill);
  // Within one tick: X hands over, Y takes control and starts a skill of its own.
  EXPECT_EQ(Send("x", "release_control", 0.5).status, ReplyStatus::kOk);
  EXPECT_EQ(Send("y", "acquire_control", 0.501).status, ReplyStatus::kOk);
  EXPECT_EQ(Skill("y", 1, 3.0, 0.502).status, ReplyStatus::kOk);
  controller_.Tick();
  const ControllerStatus s = controller_.status();
  EXPECT_EQ(s.task.state, TaskState::kRunning) << s.task.message.data();
  EXPECT_STREQ(s.task.client_id.data(), "y");
  // Y's own lease, when it lapses, ends Y's task.
  handler_.Poll(1.6);
  controller_.Tick();
  EXPECT_EQ(controller_.status().task.state, TaskState::kLeaseLost);
}

TEST_F(RequestHandlerTest, ReleasingControlStopsTheMotion) {
  ASSERT_EQ(Send("a", "acquire_control").status, ReplyStatus::kOk);
  ASSERT_EQ(Skill("a", 0, 30.0).status, ReplyStatus::kOk);
  for (int i = 0; i < 150; ++i) controller_.Tick();
  ASSERT_EQ(controller_.status().mode, Mode::kSkill);
  EXPECT_EQ(Send("a", "release_control", 0.5).status, ReplyStatus::kOk);
  controller_.Tick();
  EXPECT_EQ(controller_.status().mode, Mode::kStand);
  EXPECT_EQ(controller_.status().task.state, TaskState::kCancelled);
  EXPECT_EQ(Send("a", "release_control", 0.6).status, ReplyStatus::kNotInControl);
}

}  // namespace
}  // namespace flsd
