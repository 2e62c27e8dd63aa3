#pragma once
// Fuzz: fuzz::RandomRequests sent for a while, each reply checked against the contract (a status
// the IDL defines and, when refused, a reason).

#include <gtest/gtest.h>

#include <chrono>
#include <functional>
#include <optional>
#include <string>
#include <thread>

#include "fuzz/random_requests.h"
#include "fuzz/reply_oracle.h"

namespace flsd::testutil {

// Sends `requests` for `duration`, each within every client's rate limit, and checks each reply;
// `log` says what the server said when one is not answered. Returns the number answered.
inline int Fuzz(fuzz::RawClient& raw, fuzz::RandomRequests& requests, std::chrono::milliseconds duration,
                const std::function<std::string()>& log) {
  int answered = 0;
  const auto until = std::chrono::steady_clock::now() + duration;
  while (std::chrono::steady_clock::now() < until) {
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
    const fuzz::RawRequest r = requests.Next();
    const std::optional<fuzz::RawReply> reply = raw.Call(r, std::chrono::seconds(2));
    EXPECT_TRUE(reply) << "'" << r.call << "' from '" << r.client_id << "' (id " << r.request_id
                       << ") was not answered\n" << log();
    if (!reply) return answered;
    ++answered;
    EXPECT_EQ(fuzz::ContractViolation(*reply), "") << r.call;
  }
  return answered;
}

}  // namespace flsd::testutil
