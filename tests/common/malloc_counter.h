#pragma once
// Counts heap allocations made while a scope runs. Defining malloc in the test executable
// interposes it for every library the process uses, Eigen and MuJoCo included, so include this
// header in exactly one source file of a test executable.

#include <atomic>
#include <cstddef>

extern "C" void* __libc_malloc(size_t size);
static std::atomic<bool> g_count_mallocs{false};
static std::atomic<long> g_mallocs{0};
extern "C" void* malloc(size_t size) {
  if (g_count_mallocs.load(std::memory_order_relaxed)) g_mallocs.fetch_add(1, std::memory_order_relaxed);
  return __libc_malloc(size);
}

namespace flsd::testutil {

// The number of heap allocations `f` makes.
template <class F>
long CountMallocs(F&& f) {
  g_mallocs = 0;
  g_count_mallocs = true;
  f();
  g_count_mallocs = false;
  return g_mallocs.load();
}

}  // namespace flsd::testutil
