#include "core/base/reproducible.hpp"

#include <atomic>
#include <cstdlib>
#include <cstring>

namespace sb {
namespace {

bool from_environment() {
  const char* v = std::getenv("SHEARBENCH_REPRODUCIBLE");
  return !(v != nullptr && std::strcmp(v, "") != 0 && std::strcmp(v, "0") != 0);
}

std::atomic<bool>& flag() {
  static std::atomic<bool> on{from_environment()};
  return on;
}

}  // namespace

bool timings_in_outputs() { return flag().load(); }
void set_timings_in_outputs(bool on) { flag().store(on); }

}  // namespace sb
