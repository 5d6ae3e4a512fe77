#pragma once
// SIGINT / SIGTERM as a cancel request for long CLI operations: the first signal sets a flag the
// operation polls (it then unwinds without writing partial outputs, exit code 130); a second
// signal ends the process at once. The previous handlers come back when the scope ends.
#include <atomic>

namespace sb::app {

constexpr int kExitCancelled = 130;

class InterruptScope {
 public:
  InterruptScope();
  ~InterruptScope();
  InterruptScope(const InterruptScope&) = delete;
  InterruptScope& operator=(const InterruptScope&) = delete;
  const std::atomic<bool>* flag() const;
};

}  // namespace sb::app
