#pragma once
// Wall time since a steady_clock instant, in seconds: the one definition the fits and the loop share.
#include <chrono>

namespace sb {

inline double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace sb
