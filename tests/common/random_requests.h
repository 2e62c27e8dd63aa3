#pragma once
// Random requests, well- and ill-typed, as a careless or hostile client sends them: any call
// name, ids that mostly grow but sometimes repeat, impossible deadlines, NaN and huge numbers,
// broken and explosive maps. Fuzz sends them for a while and checks that every one is answered
// with a status the IDL defines and, when refused, a reason.

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "tests/common/raw_dds_client.h"

namespace flsd::testutil {

// One of `options`, at random.
template <class C>
const auto& PickOne(std::mt19937_64& rng, const C& options) {
  return options[rng() % std::size(options)];
}

class RandomRequests {
 public:
  RandomRequests(uint64_t seed, std::vector<std::string> clients) : rng_(seed), clients_(std::move(clients)) {
    bomb_ = "polygons:\n  - &p [[0, 0], [1, 0], [1, 1], [0, 1]]\n";
    for (int i = 0; i < 2000; ++i) bomb_ += "  - *p\n";
  }

  RawRequest Next() {
    static const std::string kCalls[] = {"list_skills", "status", "execute_skill", "track_velocity", "navigate",
                                         "stop", "stand", "damp", "clear_stop", "acquire_control", "renew_control",
                                         "release_control", "reset", "", "fly", std::string(300, 'x'), "status\n"};
    static const double kNumbers[] = {0.0, -1.0, 0.3, 1.0, 2.0, 1e9, -1e300, NAN, INFINITY, -INFINITY, 1e-300};
    static const int64_t kDeadlines[] = {0, 0, 0, INT64_MIN, INT64_MAX, -1, 1};
    const std::string maps[] = {"", "bounds: [-5, 5, -5, 5]\n",
                                "bounds: [-5, 5, -5, 5]\ncircles: [{center: [2, 0], radius: 0.5}]\n", "bounds: [1]",
                                "{{{", std::string(4000, '[') + std::string(4000, ']'), bomb_,
                                "bounds: [-.nan, 1, 0, 1]", "circles: [{center: *x, radius: 1}]", "robot_radius: 1e400"};
    RawRequest r;
    r.client_id = PickOne(rng_, clients_);
    // Mostly growing ids, sometimes a repeat or an older one.
    uint64_t& last = last_id_[r.client_id];
    r.request_id = rng_() % 10 == 0 ? last : last + 1 + rng_() % 3;
    last = std::max(last, r.request_id);
    r.deadline_ns = PickOne(rng_, kDeadlines);
    if (r.deadline_ns == 1) r.deadline_ns = dds_time() + 1'000'000'000;
    r.call = PickOne(rng_, kCalls);
    r.skill = static_cast<int32_t>(rng_() % 40) - 5;
    if (rng_() % 10 == 0) r.skill = rng_() % 2 ? INT32_MIN : INT32_MAX;
    r.duration = rng_() % 3 ? 0.2 + 0.1 * (rng_() % 10) : PickOne(rng_, kNumbers);
    for (double& v : r.velocity) v = PickOne(rng_, kNumbers);
    for (double& g : r.goal) g = rng_() % 2 ? 0.5 : PickOne(rng_, kNumbers);
    r.map_yaml = PickOne(rng_, maps);
    return r;
  }

 private:
  std::mt19937_64 rng_;
  std::vector<std::string> clients_;
  std::string bomb_;
  std::map<std::string, uint64_t> last_id_;
};

// Sends `requests` for `duration`, each within every client's rate limit, and checks each reply;
// `log` says what the server said when one is not answered. Returns the number answered.
inline int Fuzz(RawClient& raw, RandomRequests& requests, std::chrono::milliseconds duration,
                const std::function<std::string()>& log) {
  int answered = 0;
  const auto until = std::chrono::steady_clock::now() + duration;
  while (std::chrono::steady_clock::now() < until) {
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
    const RawRequest r = requests.Next();
    const std::optional<RawReply> reply = raw.Call(r, std::chrono::seconds(2));
    EXPECT_TRUE(reply) << "'" << r.call << "' from '" << r.client_id << "' (id " << r.request_id
                       << ") was not answered\n" << log();
    if (!reply) return answered;
    ++answered;
    EXPECT_GE(reply->status, flsd_msgs_STATUS_OK);
    EXPECT_LE(reply->status, flsd_msgs_STATUS_INTERNAL);
    EXPECT_NE(reply->status, flsd_msgs_STATUS_INTERNAL) << r.call << ": " << reply->message;
    if (reply->status != flsd_msgs_STATUS_OK) {
      EXPECT_FALSE(reply->message.empty()) << r.call;
    }
  }
  return answered;
}

}  // namespace flsd::testutil
