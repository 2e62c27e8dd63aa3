#pragma once
#include <atomic>
#include <condition_variable>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace flsd {

// `configured` threads, or every core when it is 0 (never fewer than one).
int ResolveThreadCount(int configured);

// A fixed set of worker threads that run one data-parallel loop at a time; the calling thread
// works too, so ThreadPool(1) runs everything inline with no synchronisation.
//
// Work is handed out in small chunks from a shared counter rather than in fixed shares: one env
// that resets (or falls and makes many contacts) would otherwise hold every other thread at the
// barrier; measured, fixed shares lost 10-15 % of the 2-core simulation rate.
//
// Loops here are short (a few ms) and back to back, so waiting threads spin briefly before they
// block: on a virtual machine a futex wake-up of an idle vCPU can cost a tenth of a millisecond,
// which is several percent of a simulation step.
class ThreadPool {
 public:
  explicit ThreadPool(int num_threads);
  ~ThreadPool();
  ThreadPool(const ThreadPool&) = delete;
  ThreadPool& operator=(const ThreadPool&) = delete;

  int num_threads() const { return num_threads_; }

  // Calls fn(begin, end) on disjoint chunks covering [0, n) and returns when all are done. Which
  // thread runs a chunk varies from call to call: fn must not depend on it. If fn throws, the
  // first exception is rethrown here once every thread has stopped using fn.
  void ParallelFor(int n, const std::function<void(int begin, int end)>& fn);

 private:
  void WorkerLoop();
  void RunChunks();

  static constexpr int kChunk = 2;

  const int num_threads_;
  std::vector<std::thread> workers_;
  std::mutex mutex_;  // guards the sleeping paths only
  std::condition_variable start_cv_;
  std::condition_variable done_cv_;
  const std::function<void(int, int)>* job_ = nullptr;
  int job_size_ = 0;
  std::atomic<long> generation_{0};
  std::atomic<int> next_{0};     // first index of the next chunk to hand out
  std::atomic<int> pending_{0};  // workers still busy with the current loop
  std::atomic<bool> stopping_{false};
  std::exception_ptr error_;  // the first exception thrown by fn in the current loop
};

}  // namespace flsd
