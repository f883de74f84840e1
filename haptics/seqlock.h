#pragma once
// A single-writer seqlock for small trivially copyable values crossing threads
// (sim thread -> servo loop: force models; servo loop -> sim thread: poses).
// The reader never blocks and never allocates: it copies the value and retries
// if a write overlapped the copy. The writer never waits for readers.
//
// The payload is stored as relaxed atomic words, so a torn read is not a data
// race (it is detected by the sequence number and retried); the sequence uses
// the fences of the classic scheme (Boehm, "Can seqlocks get along with
// programming language memory models?", MSPC 2012).

#include <atomic>
#include <cstdint>
#include <cstring>
#include <type_traits>

namespace bristle::haptics {

template <typename T>
class Seqlock {
  static_assert(std::is_trivially_copyable_v<T>, "Seqlock payloads are copied bytewise");
  static constexpr size_t kWords = (sizeof(T) + sizeof(std::uint64_t) - 1) / sizeof(std::uint64_t);

 public:
  Seqlock() { store(T{}); }

  // Writer side (one thread only).
  void store(const T& value) {
    std::uint64_t buf[kWords] = {};
    std::memcpy(buf, &value, sizeof(T));
    const std::uint64_t s = seq_.load(std::memory_order_relaxed);
    seq_.store(s + 1, std::memory_order_relaxed);  // odd: write in progress
    std::atomic_thread_fence(std::memory_order_release);
    for (size_t i = 0; i < kWords; ++i) words_[i].store(buf[i], std::memory_order_relaxed);
    seq_.store(s + 2, std::memory_order_release);
  }

  // Reader side (any thread). Returns the number of attempts it took (>= 1).
  int load(T* out) const {
    std::uint64_t buf[kWords];
    for (int attempt = 1;; ++attempt) {
      const std::uint64_t s0 = seq_.load(std::memory_order_acquire);
      if (s0 & 1) continue;  // a write is in progress: it finishes in a few ns
      for (size_t i = 0; i < kWords; ++i) buf[i] = words_[i].load(std::memory_order_relaxed);
      std::atomic_thread_fence(std::memory_order_acquire);
      if (seq_.load(std::memory_order_relaxed) == s0) {
        std::memcpy(out, buf, sizeof(T));
        return attempt;
      }
    }
  }
  T load() const {
    T v;
    load(&v);
    return v;
  }
  // Number of completed stores.
  std::uint64_t version() const { return seq_.load(std::memory_order_acquire) / 2; }

 private:
  std::atomic<std::uint64_t> seq_{0};
  std::atomic<std::uint64_t> words_[kWords];
};

}  // namespace bristle::haptics
