// Read your writes: an OK reply means that the call's effect is visible to the next request. Every
// ordered pair of the calls that change the server's state (api/calls.h), sent by one client back
// to back with no pause to the real skilld on loopback, each pair from a known state (in control,
// no stop latched, the simulation reset, every earlier request applied): the second reply must be
// the one the client contract gives after the first.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "api/calls.h"
#include "tests/common/raw_dds_client.h"
#include "tests/common/skilld_fixture.h"

namespace flsd {
namespace {

using namespace std::chrono_literals;
using ::testing::IsEmpty;
using fuzz::RawReply;
using fuzz::RawRequest;
using fuzz::RawState;

// A state-changing call as the test sends it. navigate comes twice: with the server's map it is
// answered on the request thread, with a map of its own on the navigator's, once the map is read.
struct PairCall {
  Call call;
  bool own_map = false;
  std::string Label() const { return std::string(CallName(call)) + (own_map ? " (own map)" : ""); }
};

std::vector<PairCall> StateChangingCalls() {
  std::vector<PairCall> calls;
  for (const CallSpec& spec : kCallSpecs) {
    if (spec.call == Call::kListSkills || spec.call == Call::kStatus) continue;
    calls.push_back({spec.call});
    if (spec.call == Call::kNavigate) calls.push_back({spec.call, true});
  }
  return calls;
}

// What the server holds after the first call of a pair answered OK.
struct Held {
  bool in_control = true;
  bool stop_latched = false;
};

Held After(Call first) {
  if (first == Call::kReleaseControl) return {false, false};
  if (first == Call::kDamp) return {true, true};
  return {};
}

// The reply the client contract gives to `call` from the client, and a part of its message.
struct Expected {
  flsd_msgs_ReplyStatus status = flsd_msgs_STATUS_OK;
  std::string message;
};

Expected Contract(Call call, const Held& held) {
  const bool needs_lease = Spec(call).needs_control || call == Call::kRenewControl || call == Call::kReleaseControl;
  if (needs_lease && !held.in_control) return {flsd_msgs_STATUS_NOT_IN_CONTROL, ""};
  if (call == Call::kClearStop) {
    return {flsd_msgs_STATUS_OK, held.stop_latched ? "emergency stop cleared" : "no emergency stop is latched"};
  }
  // A latched emergency stop refuses a stand, a reset and every motion; stop stays open.
  if (held.stop_latched && (call == Call::kStand || call == Call::kReset || Spec(call).long_running)) {
    return {flsd_msgs_STATUS_SAFETY_STOP, "an emergency stop from holder is latched"};
  }
  return {};
}

class SkilldCallPairsTest : public testutil::RawSkilldFixture {
 protected:
  RawReply Send(const PairCall& c) {
    RawRequest r = Request("holder", CallName(c.call));
    r.skill = 0;  // stands still (the shipped library's)
    r.duration = c.call == Call::kNavigate ? 0.0 : 2.0;
    r.velocity = {0.3, 0.0, 0.0};
    r.goal = {-1.0, 0.0};  // free on the server's map (configs/maps/demo.yaml) and on the own one
    if (c.own_map) r.map_yaml = "bounds: [-5, 5, -5, 5]\nrobot_radius: 0.35\n";
    const std::optional<RawReply> reply = raw_->Call(r);
    EXPECT_TRUE(reply) << c.Label() << " was not answered";
    return reply.value_or(RawReply{});
  }
  RawReply Send(Call call) { return Send(PairCall{call}); }

  // Two ticks after the newest state sample: whatever was submitted before has been applied,
  // whenever its reply came.
  void Settle() {
    const std::optional<RawState> now = raw_->WaitForState([](const RawState&) { return true; }, 2s);
    ASSERT_TRUE(now) << "no state";
    ASSERT_TRUE(raw_->WaitForState([&](const RawState& s) { return s.tick >= now->tick + 2; }, 2s));
  }

  // In control, no stop latched, the simulation reset; then what `first` needs to change something.
  void FromKnownState(Call first) {
    Settle();
    ASSERT_EQ(Send(Call::kAcquireControl).status, flsd_msgs_STATUS_OK);
    ASSERT_EQ(Send(Call::kClearStop).status, flsd_msgs_STATUS_OK);
    Settle();
    const RawReply reset = Send(Call::kReset);
    ASSERT_EQ(reset.status, flsd_msgs_STATUS_OK) << reset.message;
    if (first == Call::kClearStop) {
      ASSERT_EQ(Send(Call::kDamp).status, flsd_msgs_STATUS_OK);
    } else if (first == Call::kAcquireControl) {
      ASSERT_EQ(Send(Call::kReleaseControl).status, flsd_msgs_STATUS_OK);
    }
    Settle();
  }
};

TEST_F(SkilldCallPairsTest, EveryOkReplysEffectIsSeenByTheNextRequest) {
  const std::vector<PairCall> calls = StateChangingCalls();
  std::vector<std::string> broken;
  for (const PairCall& first : calls) {
    for (const PairCall& second : calls) {
      const std::string pair = first.Label() + " then " + second.Label();
      FromKnownState(first.call);
      if (HasFatalFailure()) return;
      const RawReply a = Send(first);
      ASSERT_EQ(a.status, flsd_msgs_STATUS_OK) << pair << ": " << a.message;
      const RawReply b = Send(second);
      const Expected want = Contract(second.call, After(first.call));
      if (b.status != want.status || b.message.find(want.message) == std::string::npos) {
        broken.push_back(pair + ": " + dds::StatusName(b.status) + " '" + b.message + "', not " +
                         dds::StatusName(want.status) + (want.message.empty() ? "" : " '" + want.message + "'"));
      }
    }
  }
  EXPECT_THAT(broken, IsEmpty()) << broken.size() << " of " << calls.size() * calls.size() << " pairs";
}

}  // namespace
}  // namespace flsd
