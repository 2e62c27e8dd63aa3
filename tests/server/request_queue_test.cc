// RequestQueue: tickets, and the damps a tick takes: the newest press, and the newest from another
// client, so that one presser's press is not lost to another's.

#include "server/request_queue.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace flsd {
namespace {

ControlRequest Damp(const char* client) {
  ControlRequest damp;
  damp.kind = ControlRequest::Kind::kDamp;
  SetText(damp.client_id, client);
  return damp;
}

// The pressers of the damps the next tick applies, in its order.
std::vector<std::string> TakeDamps(RequestQueue& queue) {
  std::vector<std::string> pressers;
  queue.TakeAll([&](const ControlRequest& request) {
    if (request.kind == ControlRequest::Kind::kDamp) pressers.emplace_back(request.client_id.data());
  });
  return pressers;
}

using Pressers = std::vector<std::string>;

TEST(RequestQueue, KeepsTheNewestDampAndTheNewestFromAnotherClient) {
  RequestQueue queue;
  queue.SubmitUrgent(Damp("a"));
  queue.SubmitUrgent(Damp("b"));
  EXPECT_EQ(TakeDamps(queue), (Pressers{"a", "b"}));
  queue.SubmitUrgent(Damp("a"));
  queue.SubmitUrgent(Damp("a"));
  EXPECT_EQ(TakeDamps(queue), (Pressers{"a"}));
  queue.SubmitUrgent(Damp("a"));
  queue.SubmitUrgent(Damp("b"));
  queue.SubmitUrgent(Damp("b"));
  EXPECT_EQ(TakeDamps(queue), (Pressers{"a", "b"}));
  // A third client's press is as new as the second's: a's adds nothing that b's does not.
  queue.SubmitUrgent(Damp("a"));
  queue.SubmitUrgent(Damp("b"));
  queue.SubmitUrgent(Damp("c"));
  EXPECT_EQ(TakeDamps(queue), (Pressers{"b", "c"}));
  EXPECT_EQ(TakeDamps(queue), Pressers{});
}

TEST(RequestQueue, EveryRequestAppliedCarriesItsTicket) {
  RequestQueue queue;
  ControlRequest stand;
  stand.kind = ControlRequest::Kind::kStand;
  std::vector<uint64_t> tickets = {queue.Submit(stand), queue.SubmitUrgent(Damp("a")), queue.Submit(stand),
                                   queue.SubmitUrgent(Damp("b"))};
  std::vector<uint64_t> applied;
  const uint64_t newest = queue.TakeAll([&](const ControlRequest& request) { applied.push_back(request.ticket); });
  EXPECT_EQ(newest, tickets.back());
  EXPECT_EQ(applied, (std::vector<uint64_t>{tickets[0], tickets[2], tickets[1], tickets[3]}));  // the queue, then the damps
}

}  // namespace
}  // namespace flsd
