#include "render/step_pipeline.h"

#include <sched.h>

#include <array>
#include <condition_variable>
#include <exception>
#include <mutex>
#include <thread>

namespace bristle::render {

int defaultRenderThreads() {
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof set, &set) != 0) return 1;
  return CPU_COUNT(&set) >= 2 ? 2 : 1;
}

namespace {

// Thrown on the stepping thread when the drawing side gave up; caught there.
struct StepsAbandoned {};

// A ring of kStepsAhead solved states between the two threads. The producer
// copies into the free slot at head_ and the consumer reads the slot at tail_
// outside the lock: neither slot is the other's until count_ says so, and the
// mutex orders the copies.
class StateRing {
 public:
  struct Slot {
    BrushState state;
    int step = 0, steps = 0;
  };

  // Stepping thread: waits for a free slot; throws StepsAbandoned after abandon().
  void push(const BrushState& state, int step, int steps) {
    std::unique_lock lock(mutex_);
    not_full_.wait(lock, [&] { return count_ < kStepsAhead || abandoned_; });
    if (abandoned_) throw StepsAbandoned{};
    Slot& slot = slots_[static_cast<size_t>(head_)];
    lock.unlock();
    slot.state = state;  // copy-assigned: reuses the slot's vectors
    slot.step = step;
    slot.steps = steps;
    lock.lock();
    head_ = (head_ + 1) % kStepsAhead;
    ++count_;
    not_empty_.notify_one();
  }
  // Stepping thread, last: no more states; `error` (or null) for the caller.
  void finish(std::exception_ptr error) {
    std::lock_guard lock(mutex_);
    finished_ = true;
    error_ = std::move(error);
    not_empty_.notify_one();
  }
  // Drawing thread: the oldest waiting state, or null once the stepping
  // finished and every state was taken. The slot stays the consumer's until pop().
  const Slot* front() {
    std::unique_lock lock(mutex_);
    not_empty_.wait(lock, [&] { return count_ > 0 || finished_; });
    return count_ > 0 ? &slots_[static_cast<size_t>(tail_)] : nullptr;
  }
  void pop() {
    std::lock_guard lock(mutex_);
    tail_ = (tail_ + 1) % kStepsAhead;
    --count_;
    not_full_.notify_one();
  }
  void abandon() {
    std::lock_guard lock(mutex_);
    abandoned_ = true;
    not_full_.notify_one();
  }
  std::exception_ptr error() {
    std::lock_guard lock(mutex_);
    return error_;
  }

 private:
  std::mutex mutex_;
  std::condition_variable not_full_, not_empty_;
  std::array<Slot, kStepsAhead> slots_;
  int head_ = 0, tail_ = 0, count_ = 0;
  bool finished_ = false, abandoned_ = false;
  std::exception_ptr error_;
};

}  // namespace

void walkAhead(Stepper& stepper, const Trajectory& trajectory, const StepCallback& on_step) {
  StateRing ring;
  std::thread stepping([&] {
    try {
      stepper.walk(trajectory, [&](const BrushState& state, int step, int steps) {
        ring.push(state, step, steps);
      });
      ring.finish(nullptr);
    } catch (const StepsAbandoned&) {
      ring.finish(nullptr);
    } catch (...) {
      ring.finish(std::current_exception());
    }
  });
  try {
    while (const StateRing::Slot* slot = ring.front()) {
      if (on_step) on_step(slot->state, slot->step, slot->steps);
      ring.pop();
    }
  } catch (...) {
    ring.abandon();
    stepping.join();
    throw;
  }
  stepping.join();
  if (std::exception_ptr error = ring.error()) std::rethrow_exception(error);
}

}  // namespace bristle::render
