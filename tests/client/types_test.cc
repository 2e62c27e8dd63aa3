// The client's own types: names from the shared tables, replies described for people, task ends,
// and the yaw of a known orientation.

#include <gtest/gtest.h>

#include <cmath>

#include "client/types.h"

namespace flsd {
namespace {

TEST(ClientTypesTest, EnumsAreNamedAsOnTheWire) {
  EXPECT_STREQ(Name(ReplyStatus::kOk), "ok");
  EXPECT_STREQ(Name(ReplyStatus::kSafetyStop), "safety stop");
  EXPECT_STREQ(Name(ReplyStatus::kInternal), "internal error");
  EXPECT_STREQ(Name(ReplyStatus::kNoReply), "no reply");
  EXPECT_STREQ(Name(Mode::kIdle), "idle");
  EXPECT_STREQ(Name(Mode::kDamp), "damp");
  EXPECT_STREQ(Name(TaskState::kNone), "none");
  EXPECT_STREQ(Name(TaskState::kNoPath), "no path");
  EXPECT_STREQ(Name(TaskState::kTimeout), "timeout");
}

TEST(ClientTypesTest, ARepliesDescriptionHasItsStatusMessageAndSafetyReport) {
  Reply r;
  EXPECT_FALSE(r.answered());
  EXPECT_EQ(r.Describe(), "no reply from skilld");
  r.status = ReplyStatus::kNotInControl;
  r.message = "control is held by x";
  EXPECT_TRUE(r.answered());
  EXPECT_FALSE(r.ok());
  EXPECT_EQ(r.Describe(), "not in control: control is held by x");
  r.status = ReplyStatus::kOk;
  r.safety_report = "tilt 1.2 rad";
  EXPECT_EQ(r.Describe(), "ok: control is held by x [safety: tilt 1.2 rad]");
  const CallError error(r);
  EXPECT_STREQ(error.what(), r.Describe().c_str());
  EXPECT_EQ(error.reply().message, r.message);
}

TEST(ClientTypesTest, ATaskHasEndedOnceItNeitherIsUnreportedNorRunning) {
  TaskReport t;
  EXPECT_FALSE(t.ended());
  t.state = TaskState::kRunning;
  EXPECT_FALSE(t.ended());
  for (TaskState s : {TaskState::kSucceeded, TaskState::kCancelled, TaskState::kSafetyStop, TaskState::kPreempted,
                      TaskState::kLeaseLost, TaskState::kNoPath, TaskState::kTimeout}) {
    t.state = s;
    EXPECT_TRUE(t.ended()) << Name(s);
  }
}

TEST(ClientTypesTest, YawOfKnownOrientations) {
  StateReport s;
  s.orientation = {1.0, 0.0, 0.0, 0.0};
  EXPECT_NEAR(s.yaw(), 0.0, 1e-12);
  s.orientation = {std::cos(M_PI / 4), 0.0, 0.0, std::sin(M_PI / 4)};  // 90 deg about z
  EXPECT_NEAR(s.yaw(), M_PI / 2, 1e-12);
  s.orientation = {std::cos(-0.3), 0.0, 0.0, std::sin(-0.3)};
  EXPECT_NEAR(s.yaw(), -0.6, 1e-12);
}

}  // namespace
}  // namespace flsd
