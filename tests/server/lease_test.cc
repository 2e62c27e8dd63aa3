// ControlLease with injected time: one holder, renewal by any request, expiry after silence.

#include "server/lease.h"

#include <gtest/gtest.h>

namespace flsd {
namespace {

TEST(ControlLease, OneHolderAtATime) {
  ControlLease lease(1.0);
  EXPECT_FALSE(lease.held());
  EXPECT_TRUE(lease.Acquire("a", 0.0));
  EXPECT_FALSE(lease.Acquire("b", 0.5));
  EXPECT_EQ(lease.holder(), "a");
  EXPECT_TRUE(lease.Acquire("a", 0.6));  // the holder renews by acquiring again
}

TEST(ControlLease, LapsesAfterTheTimeoutWithoutRenewal) {
  ControlLease lease(1.0);
  ASSERT_TRUE(lease.Acquire("a", 0.0));
  EXPECT_TRUE(lease.Renew("a", 0.9));
  EXPECT_FALSE(lease.Expire(1.9));  // 1.0 s after the renewal: still held
  EXPECT_TRUE(lease.Expire(1.91));
  EXPECT_FALSE(lease.Expire(1.92));  // reported once
  EXPECT_FALSE(lease.held());
  EXPECT_FALSE(lease.Renew("a", 2.0));
  EXPECT_TRUE(lease.Acquire("b", 2.0));
}

TEST(ControlLease, OnlyTheHolderRenewsOrReleases) {
  ControlLease lease(1.0);
  ASSERT_TRUE(lease.Acquire("a", 0.0));
  EXPECT_FALSE(lease.Renew("b", 0.1));
  EXPECT_FALSE(lease.Release("b"));
  EXPECT_TRUE(lease.held());
  EXPECT_TRUE(lease.Release("a"));
  EXPECT_FALSE(lease.held());
  EXPECT_FALSE(lease.Release("a"));
}

TEST(ControlLease, ALapsedLeaseGoesToTheNextClient) {
  ControlLease lease(0.5);
  ASSERT_TRUE(lease.Acquire("a", 0.0));
  EXPECT_TRUE(lease.Acquire("b", 0.6));
  EXPECT_EQ(lease.holder(), "b");
}

}  // namespace
}  // namespace flsd
