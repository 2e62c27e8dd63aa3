// Read your writes on the state topic: when skilld answers a call `ok`, the state topic already
// shows the call's effect. An independent client over raw DDS calls the real skilld on loopback
// and compares writer timestamps (one clock on loopback): for every call whose effect the state
// topic shows (the mode, latched faults, the task, the control holder), the newest sample
// published before the reply shows it, and so does the first one published after it.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "tests/common/raw_dds_client.h"
#include "tests/common/skilld_fixture.h"

namespace flsd {
namespace {

using namespace std::chrono_literals;
using ::testing::IsEmpty;
using fuzz::RawReply;
using fuzz::RawRequest;
using fuzz::RawState;

// What the state topic must show after an `ok` reply, and how to say it.
struct Shows {
  std::string what;
  std::function<bool(const RawState&)> holds;
};

std::string Describe(const RawState& s) {
  return std::string("tick ") + std::to_string(s.tick) + ": mode " + dds::ModeName(s.mode) + ", faults " +
         std::to_string(s.faults) + ", controller '" + s.controller + "', task " + s.task_call + " " +
         std::to_string(s.task_request_id) + " from '" + s.task_client_id + "' " + dds::TaskStateName(s.task_state);
}

class SkilldStateAfterReplyTest : public testutil::SkilldFixture {
 protected:
  void SetUp() override {
    SkilldFixture::SetUp();
    StartServer();
    // Every sample kept until read: the one just before a reply must not be displaced by newer ones.
    raw_ = std::make_unique<fuzz::RawClient>(domain_, partition_, dds::SecurityConfig{}, /*state_depth=*/256);
    ASSERT_TRUE(raw_->WaitForServer(15s)) << server_->Log();
    newest_ = raw_->WaitForState([](const RawState&) { return true; }, 2s);
    ASSERT_TRUE(newest_) << "no state sample";
  }

  RawRequest Request(const std::string& client, const std::string& call) {
    RawRequest r;
    r.client_id = client;
    r.request_id = ++next_id_;
    r.call = call;
    return r;
  }

  // Sends `r`, which must be answered ok, and checks `shows` on the samples either side of the reply.
  void Expect(const RawRequest& r, const Shows& shows) {
    const std::string label = r.call + " from " + r.client_id;
    if (std::optional<RawState> s = raw_->TakeLatestState()) newest_ = std::move(s);
    const std::optional<RawReply> reply = raw_->Call(r);
    ASSERT_TRUE(reply) << label << " was not answered";
    ASSERT_EQ(reply->status, flsd_msgs_STATUS_OK) << label << ": " << reply->message;
    ASSERT_GT(reply->published_ns, 0) << label;
    std::optional<RawState> before = newest_;
    const std::optional<RawState> after = raw_->WaitForState(
        [&](const RawState& s) {
          if (s.published_ns > reply->published_ns) return true;
          before = s;
          return false;
        },
        2s);
    ASSERT_TRUE(before) << label << ": no state sample before its reply";
    ASSERT_TRUE(after) << label << ": no state sample within 2 s of its reply";
    newest_ = after;
    if (!shows.holds(*before)) {
      broken_.push_back(label + ": ok, but the last state sample before the reply did not show " + shows.what +
                        " (" + Describe(*before) + ")");
    }
    if (!shows.holds(*after)) {
      broken_.push_back(label + ": ok, but the first state sample after the reply did not show " + shows.what +
                        " (" + Describe(*after) + ")");
    }
  }
  void Expect(const std::string& client, const std::string& call, const Shows& shows) {
    Expect(Request(client, call), shows);
  }

  static Shows Controller(const std::string& id) {
    return {"controller '" + id + "'", [id](const RawState& s) { return s.controller == id; }};
  }
  static Shows InMode(flsd_msgs_Mode mode, bool faults) {
    return {std::string("mode ") + dds::ModeName(mode) + (faults ? " with a fault latched" : " with no fault"),
            [=](const RawState& s) { return s.mode == mode && (s.faults != 0) == faults; }};
  }
  static Shows Task(const std::string& client, uint64_t request_id, flsd_msgs_TaskState state) {
    return {"task " + std::to_string(request_id) + " from '" + client + "' " + dds::TaskStateName(state),
            [=](const RawState& s) {
              return s.task_client_id == client && s.task_request_id == request_id && s.task_state == state;
            }};
  }

  std::unique_ptr<fuzz::RawClient> raw_;
  uint64_t next_id_ = static_cast<uint64_t>(dds_time());
  std::optional<RawState> newest_;
  std::vector<std::string> broken_;
};

TEST_F(SkilldStateAfterReplyTest, EveryOkReplyComesAfterTheStateSampleThatShowsItsEffect) {
  Expect("alice", "acquire_control", Controller("alice"));
  Expect("alice", "reset", InMode(flsd_msgs_MODE_STAND, false));
  Expect("alice", "damp", InMode(flsd_msgs_MODE_DAMP, true));
  Expect("alice", "clear_stop", InMode(flsd_msgs_MODE_IDLE, false));
  Expect("alice", "stand", InMode(flsd_msgs_MODE_STAND, false));
  RawRequest skill = Request("alice", "execute_skill");
  skill.skill = 0;  // stands still (the shipped library's)
  skill.duration = 5.0;
  Expect(skill, Task("alice", skill.request_id, flsd_msgs_TASK_RUNNING));
  Expect("alice", "stop", Task("alice", skill.request_id, flsd_msgs_TASK_CANCELLED));
  Expect("alice", "release_control", Controller(""));
  // The lease changes hands: the newcomer is named before it is told it holds control.
  Expect("bob", "acquire_control", Controller("bob"));
  Expect("bob", "release_control", Controller(""));
  EXPECT_THAT(broken_, IsEmpty()) << server_->Log();
}

// A lease taken over and over, each time by a client that another has just released it to.
TEST_F(SkilldStateAfterReplyTest, TheControllerIsNamedBeforeEveryAcquireIsAnswered) {
  for (int i = 0; i < 20; ++i) {
    const std::string id = i % 2 == 0 ? "alice" : "bob";
    Expect(id, "acquire_control", Controller(id));
    Expect(id, "release_control", Controller(""));
  }
  EXPECT_THAT(broken_, IsEmpty());
}

// A reply sent at once (status) says no more than the state topic has shown: its tick is one
// the topic published before the reply, and it names that sample's holder and mode. A lease
// that lapses while another client polls is where it once did not: the reply said "control free"
// while the newest sample still named the old holder.
TEST_F(SkilldStateAfterReplyTest, AStatusReplyNeverRunsAheadOfTheStateTopic) {
  std::vector<RawState> samples;
  const auto drain = [&] {
    raw_->WaitForState([&](const RawState& s) { samples.push_back(s); return false; }, 0ms);
  };
  ASSERT_EQ(raw_->Call(Request("alice", "acquire_control"))->status, flsd_msgs_STATUS_OK);
  int checked = 0;
  const auto until = std::chrono::steady_clock::now() + 1500ms;  // past the 1-s lease's lapse
  while (std::chrono::steady_clock::now() < until) {
    const std::optional<RawReply> reply = raw_->Call(Request("bob", "status"));
    ASSERT_TRUE(reply);
    drain();
    // "mode M..., t T s, control C, faults F"
    const std::string& text = reply->message;
    const size_t t_at = text.find(", t "), control_at = text.find(", control "), faults_at = text.find(", faults ");
    ASSERT_TRUE(t_at != std::string::npos && control_at != std::string::npos && faults_at != std::string::npos) << text;
    const double t = std::stod(text.substr(t_at + 4));
    const std::string control = text.substr(control_at + 10, faults_at - control_at - 10);
    const RawState* shown = nullptr;  // the sample of the reply's tick, published before it
    for (const RawState& s : samples) {
      if (s.published_ns < reply->published_ns && std::abs(s.time - t) < 0.005) shown = &s;
    }
    if (shown == nullptr) {
      broken_.push_back("'" + text + "': no sample of that tick was published before the reply");
      continue;
    }
    ++checked;
    const std::string mode = std::string("mode ") + dds::ModeName(shown->mode);
    if (control != (shown->controller.empty() ? "free" : shown->controller) || text.compare(0, mode.size(), mode) != 0) {
      broken_.push_back("'" + text + "' against the sample of its tick: " + Describe(*shown));
    }
    std::this_thread::sleep_for(1ms);
  }
  EXPECT_GT(checked, 100);
  EXPECT_THAT(broken_, IsEmpty());
}

}  // namespace
}  // namespace flsd
