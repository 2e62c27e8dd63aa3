#include "fuzz/reply_oracle.h"

#include <gtest/gtest.h>

namespace flsd::fuzz {
namespace {

using Clock = ReplyOracle::Clock;

// A lease timeout of 1 s, durations up to 600 s.
ServerFacts Facts() { return ServerFacts(1.0, 600.0); }

RawRequest Request(const std::string& call, uint64_t id, const std::string& client = "alice") {
  RawRequest r;
  r.client_id = client;
  r.request_id = id;
  r.call = call;
  r.duration = 1.0;
  return r;
}

RawReply Reply(flsd_msgs_ReplyStatus status, const std::string& message = "") {
  RawReply reply;
  reply.status = status;
  reply.message = message;
  return reply;
}

TEST(ContractViolation, InternalErrorsAndReasonlessRefusalsBreakTheContract) {
  EXPECT_EQ(ContractViolation(Reply(flsd_msgs_STATUS_OK)), "");
  EXPECT_EQ(ContractViolation(Reply(flsd_msgs_STATUS_NOT_IN_CONTROL, "bob holds the lease")), "");
  EXPECT_EQ(ContractViolation(Reply(flsd_msgs_STATUS_NOT_IN_CONTROL)), "a refusal without a reason");
  EXPECT_EQ(ContractViolation(Reply(flsd_msgs_STATUS_INTERNAL, "oops")), "internal error: oops");
  EXPECT_EQ(ContractViolation(Reply(static_cast<flsd_msgs_ReplyStatus>(42), "?")), "status 42 is not in the IDL");
}

TEST(ReplyOracle, AMotionWithoutTheLeaseMayOnlyBeRefused) {
  ReplyOracle oracle(Facts());
  const Expectation e = oracle.Expect(Request("stand", 1), Clock::now(), 0);
  EXPECT_TRUE(e.allowed.Has(flsd_msgs_STATUS_NOT_IN_CONTROL));
  EXPECT_FALSE(e.allowed.Has(flsd_msgs_STATUS_OK)) << e.rule;  // an ok here is a wrong reply
}

TEST(ReplyOracle, TheHolderOfAFreshLeaseMustNotBeToldItIsNotInControl) {
  ReplyOracle oracle(Facts());
  const Clock::time_point t0 = Clock::now();
  const RawRequest acquire = Request("acquire_control", 1);
  oracle.Learn(acquire, oracle.Expect(acquire, t0, 0), t0, Reply(flsd_msgs_STATUS_OK));
  const Expectation e = oracle.Expect(Request("stand", 2), t0 + std::chrono::milliseconds(10), 0);
  EXPECT_TRUE(e.allowed.Has(flsd_msgs_STATUS_OK));
  EXPECT_FALSE(e.allowed.Has(flsd_msgs_STATUS_NOT_IN_CONTROL)) << e.rule;
  // Another client meanwhile cannot take it.
  const Expectation other = oracle.Expect(Request("acquire_control", 1, "bob"), t0, 0);
  EXPECT_TRUE(other.allowed.Has(flsd_msgs_STATUS_NOT_IN_CONTROL));
}

TEST(ReplyOracle, HeaderChecksComeFirstAndAllowOneAnswer) {
  ReplyOracle oracle(Facts());
  const Clock::time_point t = Clock::now();
  oracle.Expect(Request("status", 5), t, 0);
  EXPECT_TRUE(oracle.Expect(Request("status", 5), t, 0).allowed.Has(flsd_msgs_STATUS_DUPLICATE));
  EXPECT_FALSE(oracle.Expect(Request("status", 4), t, 0).allowed.Has(flsd_msgs_STATUS_OK));

  RawRequest late = Request("status", 6);
  late.deadline_ns = 1000;
  const Expectation expired = oracle.Expect(late, t, 2000);
  EXPECT_TRUE(expired.allowed.Has(flsd_msgs_STATUS_DEADLINE_EXCEEDED));
  EXPECT_FALSE(expired.allowed.Has(flsd_msgs_STATUS_OK));

  const Expectation nameless = oracle.Expect(Request("status", 1, ""), t, 0);
  EXPECT_TRUE(nameless.allowed.Has(flsd_msgs_STATUS_INVALID_ARGUMENT));
  EXPECT_FALSE(nameless.allowed.Has(flsd_msgs_STATUS_OK));

  EXPECT_FALSE(oracle.Expect(Request("fly", 7), t, 0).allowed.Has(flsd_msgs_STATUS_OK));
}

TEST(ReplyOracle, ABadArgumentIsOnlyEverInvalidForTheHolder) {
  ReplyOracle oracle(Facts());
  const Clock::time_point t0 = Clock::now();
  const RawRequest acquire = Request("acquire_control", 1);
  oracle.Learn(acquire, oracle.Expect(acquire, t0, 0), t0, Reply(flsd_msgs_STATUS_OK));
  RawRequest forever = Request("track_velocity", 2);
  forever.duration = 601.0;  // over the 600 s maximum
  const Expectation e = oracle.Expect(forever, t0, 0);
  EXPECT_TRUE(e.allowed.Has(flsd_msgs_STATUS_INVALID_ARGUMENT));
  EXPECT_FALSE(e.allowed.Has(flsd_msgs_STATUS_OK)) << e.rule;
}

}  // namespace
}  // namespace flsd::fuzz
