#pragma once
// The one clock every stage's timing in Stats is read from.
#include <chrono>

namespace expanse::detail {

using Clock = std::chrono::steady_clock;

/// Milliseconds elapsed since `start`, the unit every timing in Stats uses.
inline double ms_since(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

/// Times one stage: started on construction, read with ms().
class Stopwatch {
 public:
  Stopwatch() : start_(Clock::now()) {}
  double ms() const { return ms_since(start_); }
  void restart() { start_ = Clock::now(); }

 private:
  Clock::time_point start_;
};

}  // namespace expanse::detail
