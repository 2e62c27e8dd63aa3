#include "core/thread_pool.h"

#include <algorithm>
#include <utility>

#include "core/check.h"

namespace flsd {
namespace {

// About 0.2 ms of spinning before a thread blocks.
constexpr int kSpinIterations = 4000;

inline void CpuRelax() {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();
#endif
}

}  // namespace

int ResolveThreadCount(int configured) {
  return configured > 0 ? configured : std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
}

ThreadPool::ThreadPool(int num_threads) : num_threads_(num_threads) {
  FLSD_DEMAND(num_threads >= 1);
  for (int w = 1; w < num_threads; ++w) workers_.emplace_back([this] { WorkerLoop(); });
}

ThreadPool::~ThreadPool() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
  }
  start_cv_.notify_all();
  for (std::thread& t : workers_) t.join();
}

void ThreadPool::ParallelFor(int n, const std::function<void(int, int)>& fn) {
  if (num_threads_ == 1) {
    fn(0, n);
    return;
  }
  error_ = nullptr;
  job_ = &fn;
  job_size_ = n;
  pending_.store(num_threads_ - 1, std::memory_order_relaxed);
  next_.store(0, std::memory_order_relaxed);
  {
    std::lock_guard<std::mutex> lock(mutex_);
    generation_.fetch_add(1, std::memory_order_release);
  }
  start_cv_.notify_all();
  RunChunks();
  for (int i = 0; pending_.load(std::memory_order_acquire) != 0; ++i) {
    if (i < kSpinIterations) {
      CpuRelax();
      continue;
    }
    std::unique_lock<std::mutex> lock(mutex_);
    done_cv_.wait(lock, [this] { return pending_.load(std::memory_order_acquire) == 0; });
  }
  job_ = nullptr;
  if (error_) std::rethrow_exception(std::exchange(error_, nullptr));
}

void ThreadPool::RunChunks() {
  try {
    for (;;) {
      const int begin = next_.fetch_add(kChunk, std::memory_order_relaxed);
      if (begin >= job_size_) return;
      (*job_)(begin, std::min(begin + kChunk, job_size_));
    }
  } catch (...) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!error_) error_ = std::current_exception();
    next_.store(job_size_, std::memory_order_relaxed);  // hand out no more work
  }
}

void ThreadPool::WorkerLoop() {
  long seen = 0;
  for (;;) {
    for (int i = 0; generation_.load(std::memory_order_acquire) == seen && !stopping_; ++i) {
      if (i < kSpinIterations) {
        CpuRelax();
        continue;
      }
      std::unique_lock<std::mutex> lock(mutex_);
      start_cv_.wait(lock, [&] { return generation_.load() != seen || stopping_; });
    }
    if (stopping_) return;
    seen = generation_.load(std::memory_order_acquire);
    RunChunks();
    if (pending_.fetch_sub(1, std::memory_order_acq_rel) == 1) {
      std::lock_guard<std::mutex> lock(mutex_);
      done_cv_.notify_one();
    }
  }
}

}  // namespace flsd
