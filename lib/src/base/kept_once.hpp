#pragma once
// How what a Converter keeps of a tile for its later runs is made once: the first run to claim()
// it makes it, then publish()es it (or decline()s to keep it); runs that find it claimed and not
// ready do the work as if nothing were kept. Internal.
#include <atomic>

namespace panoproj {

class KeptOnce {
 public:
  // The first caller gets true and makes it (then publish() or decline()); the others false.
  bool claim() {
    int none = kNone;
    return state_.compare_exchange_strong(none, kMaking, std::memory_order_acquire);
  }
  void publish() { state_.store(kReady, std::memory_order_release); }
  void decline() { state_.store(kDeclined, std::memory_order_release); }
  bool ready() const { return state_.load(std::memory_order_acquire) == kReady; }

 private:
  enum { kNone, kMaking, kReady, kDeclined };
  std::atomic<int> state_{kNone};
};

}  // namespace panoproj
