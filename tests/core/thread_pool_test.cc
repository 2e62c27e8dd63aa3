#include "core/thread_pool.h"

#include <gtest/gtest.h>

#include <atomic>
#include <memory>
#include <thread>
#include <vector>

namespace flsd {
namespace {

// How often ParallelFor visited each index of [0, n), plus any chunk that was empty or out of
// range.
struct Coverage {
  std::vector<int> hits;
  int bad_chunks = 0;
};

Coverage RunAndCount(ThreadPool& pool, int n) {
  std::unique_ptr<std::atomic<int>[]> hits(new std::atomic<int>[n > 0 ? n : 1]);
  for (int i = 0; i < n; ++i) hits[i] = 0;
  std::atomic<int> bad_chunks{0};
  pool.ParallelFor(n, [&](int begin, int end) {
    if (begin < 0 || end > n || begin > end || (begin == end && n > 0)) {
      ++bad_chunks;
      return;
    }
    for (int i = begin; i < end; ++i) hits[i].fetch_add(1, std::memory_order_relaxed);
  });
  Coverage c;
  c.bad_chunks = bad_chunks.load();
  for (int i = 0; i < n; ++i) c.hits.push_back(hits[i].load());
  return c;
}

class ThreadPoolCoverage : public ::testing::TestWithParam<int> {};

TEST_P(ThreadPoolCoverage, EveryIndexExactlyOnce) {
  ThreadPool pool(GetParam());
  EXPECT_EQ(pool.num_threads(), GetParam());
  for (int n : {0, 1, 7, 1000}) {
    const Coverage c = RunAndCount(pool, n);
    EXPECT_EQ(c.bad_chunks, 0) << "n = " << n;
    for (int i = 0; i < n; ++i) {
      ASSERT_EQ(c.hits[i], 1) << "index " << i << " of n = " << n;
    }
  }
}

// Back-to-back loops are the simulator's pattern; a lost wake-up or a stale chunk counter would
// hang here or miscount.
TEST_P(ThreadPoolCoverage, ManyConsecutiveLoopsAllComplete) {
  ThreadPool pool(GetParam());
  long total = 0;
  std::atomic<long> sum{0};
  for (int call = 0; call < 2000; ++call) {
    const int n = 1 + call % 13;
    total += static_cast<long>(n) * (n - 1) / 2;
    pool.ParallelFor(n, [&](int begin, int end) {
      for (int i = begin; i < end; ++i) sum.fetch_add(i, std::memory_order_relaxed);
    });
  }
  EXPECT_EQ(sum.load(), total);
}

INSTANTIATE_TEST_SUITE_P(Threads, ThreadPoolCoverage, ::testing::Values(1, 2, 3));

TEST(ThreadPool, OneThreadRunsInlineAsOneChunk) {
  ThreadPool pool(1);
  const std::thread::id caller = std::this_thread::get_id();
  int calls = 0;
  pool.ParallelFor(10, [&](int begin, int end) {
    ++calls;  // not atomic on purpose: everything runs on this thread
    EXPECT_EQ(std::this_thread::get_id(), caller);
    EXPECT_EQ(begin, 0);
    EXPECT_EQ(end, 10);
  });
  EXPECT_EQ(calls, 1);
}

}  // namespace
}  // namespace flsd
