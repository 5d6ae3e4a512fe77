#include "core/base/format.hpp"

#include <cmath>
#include <cstdio>

namespace sb {

std::string format_number(double v, const char* spec, const char* not_finite) {
  if (!std::isfinite(v)) return not_finite;
  char buf[64];
  std::snprintf(buf, sizeof buf, spec, v);
  return buf;
}

}  // namespace sb
