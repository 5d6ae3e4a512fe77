#pragma once
// The two non-finite doubles the code names: NaN marks a value that is missing (an untracked marker, an
// unmeasured statistic), infinity a bound not yet met. One definition, so no file defines its own.
#include <limits>

namespace sb {

inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
inline constexpr double kInf = std::numeric_limits<double>::infinity();

}  // namespace sb
