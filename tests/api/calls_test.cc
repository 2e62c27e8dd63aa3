// The call table: every name finds its call, unknown names find none, and the flags say which
// calls need control and which report on the state topic.

#include <gtest/gtest.h>

#include <set>
#include <string>

#include "api/calls.h"

namespace flsd {
namespace {

TEST(Calls, EveryCallNameFindsItsCallAndNamesAreUnique) {
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

TEST(Calls, UnknownAndNearMissNamesFindNothing) {
  EXPECT_FALSE(FindCall(""));
  EXPECT_FALSE(FindCall("self_destruct"));
  EXPECT_FALSE(FindCall("Status"));
  EXPECT_FALSE(FindCall("status "));
  EXPECT_FALSE(FindCall(std::string_view("status\0x", 8)));
}

TEST(Calls, LongCallsAreTheThreeMotionsAndControlGuardsEveryMotion) {
  std::set<std::string> long_running, controlled;
  for (const CallSpec& spec : kCallSpecs) {
    if (spec.long_running) long_running.insert(spec.name);
    if (spec.needs_control) controlled.insert(spec.name);
  }
  EXPECT_EQ(long_running, (std::set<std::string>{"execute_skill", "track_velocity", "navigate"}));
  EXPECT_EQ(controlled, (std::set<std::string>{"execute_skill", "track_velocity", "navigate", "stop", "stand", "reset"}));
}

TEST(Calls, KnownCallsListsEveryNameOnceInTableOrder) {
  EXPECT_EQ(KnownCalls(),
            "list_skills, status, execute_skill, track_velocity, navigate, stop, stand, damp, clear_stop, "
            "acquire_control, renew_control, release_control, reset");
}

}  // namespace
}  // namespace flsd
