#pragma once
// Progress reporting and cooperative cancellation for long operations (fits, the residual loop,
// tracking a long video). The operation polls `check()` between units of work; when the flag is set
// it throws Cancelled, which unwinds before any output is written (outputs are written only at the
// end, atomically), so a cancelled run leaves the user's files as they were.
#include <atomic>
#include <functional>
#include <stdexcept>
#include <string>

namespace sb {

class Cancelled : public std::runtime_error {
 public:
  explicit Cancelled(const std::string& where) : std::runtime_error(where + ": cancelled") {}
};

struct Progress {
  // Called with what is running and its completed fraction in [0, 1] (negative: unknown).
  std::function<void(const std::string& stage, double fraction)> report;
  const std::atomic<bool>* cancel = nullptr;

  bool cancelled() const { return cancel != nullptr && cancel->load(std::memory_order_relaxed); }
  // Throws Cancelled(where) when the flag is set.
  void check(const std::string& where) const {
    if (cancelled()) throw Cancelled(where);
  }
  void operator()(const std::string& stage, double fraction) const {
    if (report) report(stage, fraction);
  }
};

}  // namespace sb
