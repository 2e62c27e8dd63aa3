// The call table: every name finds its call, unknown names find none, and the flags say which
// calls need control and which report on the state topic.

#include <gtest/gtest.h>

#include <set>
#include <string>

#include "comm/protocol.h"

namespace flsd::dds {
namespace {

TEST(ProtocolTest, EveryCallNameFindsItsCallAndNamesAreUnique) {
  std::set<std::string> names;
  for (const CallSpec& spec : kCallSpecs) {
    ASSERT_EQ(FindCall(spec.name), spec.call) << spec.name;
    EXPECT_STREQ(CallName(spec.call), spec.name);
    names.insert(spec.name);
  }
  EXPECT_EQ(names.size(), std::size(kCallSpecs));
  EXPECT_STREQ(CallName(Call::kClearStop), "clear_stop");
  EXPECT_STREQ(CallName(Call::kTrackVelocity), "track_velocity");
}

TEST(ProtocolTest, UnknownAndNearMissNamesFindNothing) {
  EXPECT_FALSE(FindCall(""));
  EXPECT_FALSE(FindCall("self_destruct"));
  EXPECT_FALSE(FindCall("Status"));
  EXPECT_FALSE(FindCall("status "));
  EXPECT_FALSE(FindCall(std::string_view("status\0x", 8)));
}

TEST(ProtocolTest, LongCallsAreTheThreeMotionsAndControlGuardsEveryMotion) {
  std::set<std::string> long_running, controlled;
  for (const CallSpec& spec : kCallSpecs) {
    if (spec.long_running) long_running.insert(spec.name);
    if (spec.needs_control) controlled.insert(spec.name);
  }
  EXPECT_EQ(long_running, (std::set<std::string>{"execute_skill", "track_velocity", "navigate"}));
  EXPECT_EQ(controlled, (std::set<std::string>{"execute_skill", "track_velocity", "navigate", "stop", "stand", "reset"}));
}

TEST(ProtocolTest, KnownCallsListsEveryNameOnceInTableOrder) {
  EXPECT_EQ(KnownCalls(),
            "list_skills, status, execute_skill, track_velocity, navigate, stop, stand, damp, clear_stop, "
            "acquire_control, renew_control, release_control, reset");
}

TEST(ProtocolTest, EnumNamesForPeople) {
  EXPECT_STREQ(ModeName(flsd_msgs_MODE_NAVIGATE), "navigate");
  EXPECT_STREQ(StatusName(flsd_msgs_STATUS_NOT_IN_CONTROL), "not in control");
  EXPECT_STREQ(TaskStateName(flsd_msgs_TASK_LEASE_LOST), "lease lost");
}

}  // namespace
}  // namespace flsd::dds
