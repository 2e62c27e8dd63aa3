#pragma once
// Hands the newest value from one thread to another without locks or allocation: the writer
// fills a spare slot and swaps it in; the reader takes the newest slot whenever it looks. Values
// in between may be skipped; a value is never torn. One writer thread, one reader thread.

#include <array>
#include <atomic>
#include <cstdint>

namespace flsd {

template <class T>
class TripleBuffer {
 public:
  explicit TripleBuffer(const T& initial = T{}) { slots_.fill(initial); }

  // Writer: publishes `value`.
  void Write(const T& value) {
    slots_[back_] = value;
    const uint8_t previous = middle_.exchange(static_cast<uint8_t>(back_ | kFresh), std::memory_order_acq_rel);
    back_ = previous & kIndex;
  }

  // Reader: the newest value published (or the last one read, if none is newer). Returns whether
  // it is new since the last Read.
  bool Read(T& out) {
    const bool fresh = middle_.load(std::memory_order_relaxed) & kFresh;
    if (fresh) {
      const uint8_t previous = middle_.exchange(front_, std::memory_order_acq_rel);
      front_ = previous & kIndex;
    }
    out = slots_[front_];
    return fresh;
  }

 private:
  static constexpr uint8_t kIndex = 0x3, kFresh = 0x4;
  std::array<T, 3> slots_;
  uint8_t back_ = 0;                  // the writer's
  std::atomic<uint8_t> middle_{1};    // shared: index, and whether it holds an unread value
  uint8_t front_ = 2;                 // the reader's
};

}  // namespace flsd
