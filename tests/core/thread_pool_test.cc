#include "core/thread_pool.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <memory>
#include <stdexcept>
#include <string>
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

// Spins until `flag` is set, for at most a few seconds so that a broken pool fails rather than
// hangs the test.
void WaitFor(const std::atomic<bool>& flag) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (!flag.load() && std::chrono::steady_clock::now() < deadline) std::this_thread::yield();
}

// The message of the std::runtime_error that `call` throws; "" (and a failure) otherwise.
template <class F>
std::string RuntimeErrorMessage(F&& call) {
  try {
    call();
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  ADD_FAILURE() << "nothing was thrown";
  return "";
}

// The worker throws while the calling thread is still busy with its own chunk: the exception
// crosses threads, and the pool serves the next loop in full.
TEST(ThreadPool, ExceptionOnAWorkerReachesTheCaller) {
  ThreadPool pool(2);
  const std::thread::id caller = std::this_thread::get_id();
  std::atomic<bool> worker_threw{false};
  const std::string message = RuntimeErrorMessage([&] {
    pool.ParallelFor(100, [&](int begin, int end) {
      if (std::this_thread::get_id() != caller) {
        worker_threw = true;
        throw std::runtime_error("worker chunk " + std::to_string(begin));
      }
      WaitFor(worker_threw);  // so that the worker surely gets a chunk
    });
  });
  EXPECT_TRUE(worker_threw.load());
  EXPECT_EQ(message.rfind("worker chunk ", 0), 0u) << message;
  const Coverage c = RunAndCount(pool, 100);
  EXPECT_EQ(c.bad_chunks, 0);
  EXPECT_EQ(c.hits, std::vector<int>(100, 1));
}

// The caller throws while the worker is inside a chunk: ParallelFor must not return (and
// destroy fn) before that chunk has finished.
TEST(ThreadPool, ExceptionOnTheCallerWaitsForTheWorker) {
  ThreadPool pool(2);
  const std::thread::id caller = std::this_thread::get_id();
  std::atomic<bool> worker_started{false};
  std::atomic<int> active{0};
  const std::string message = RuntimeErrorMessage([&] {
    pool.ParallelFor(100, [&](int begin, int end) {
      if (std::this_thread::get_id() == caller) {
        WaitFor(worker_started);
        throw std::runtime_error("caller chunk");
      }
      ++active;
      worker_started = true;
      std::this_thread::sleep_for(std::chrono::milliseconds(30));
      --active;
    });
  });
  EXPECT_EQ(message, "caller chunk");
  EXPECT_TRUE(worker_started.load());
  EXPECT_EQ(active.load(), 0) << "ParallelFor returned while a worker was still in fn";
  const Coverage c = RunAndCount(pool, 100);
  EXPECT_EQ(c.hits, std::vector<int>(100, 1));
}

// A throw at every index in turn, whichever thread happens to run it.
TEST(ThreadPool, ThrowAtAnyIndexPropagatesAndThePoolStaysUsable) {
  ThreadPool pool(2);
  for (int bad = 0; bad < 100; ++bad) {
    const std::string message = RuntimeErrorMessage([&] {
      pool.ParallelFor(100, [&](int begin, int end) {
        for (int i = begin; i < end; ++i) {
          if (i == bad) throw std::runtime_error("index " + std::to_string(i));
        }
      });
    });
    ASSERT_EQ(message, "index " + std::to_string(bad));
    const Coverage c = RunAndCount(pool, 100);
    ASSERT_EQ(c.bad_chunks, 0) << "after a throw at " << bad;
    ASSERT_EQ(c.hits, std::vector<int>(100, 1)) << "after a throw at " << bad;
  }
}

}  // namespace
}  // namespace flsd
