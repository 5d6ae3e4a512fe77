#pragma once
// Values typed into the workbench checked where they are typed (issue 52: nothing changes silently): an
// indenter pose against the scene's gel, a parameter against its ParamSpec's range, and whether a value sits
// at a bound (a fit that ran into its bound says so).
#include <string>

#include "core/base/params.hpp"
#include "core/geometry/pose.hpp"

namespace sb {

// How far above the gel surface (z = 0 in E) the indenter origin may be typed: the pose fields' drag range.
inline constexpr double kIndenterReachAboveGel_m = 0.040;
// A value within this share of its range (of its log range for a log-scale parameter) from a bound is "at bound".
inline constexpr double kAtBoundRelMargin = 1e-3;

struct PoseCheck {
  bool accepted = true;
  std::string message;  // why it was refused ("" when accepted)
};

// `X_EI` typed for the indenter: refused when a component is not finite, when the origin is more than `reach_m`
// above the gel surface or deeper than `gel_thickness_m` into it (below the gel's back).
// @pre gel_thickness_m > 0, reach_m > 0
PoseCheck check_indenter_pose(const Pose& X_EI, double gel_thickness_m, double reach_m = kIndenterReachAboveGel_m);

struct ParamCheck {
  bool accepted = true;  // false: not a number, the value is kept
  double value = 0;      // what the parameter is set to (the bound when clamped)
  std::string note;      // said at the field when the value typed is not the value set ("" otherwise)
};

// `typed` for the parameter `spec`: as is inside [min, max], else clamped to the bound with a note; a non-finite
// value is refused with a note.
// @pre spec.min <= spec.max
ParamCheck check_param_value(const ParamSpec& spec, double typed);

// Whether `value` is within kAtBoundRelMargin of spec.min or spec.max (a switch never is).
// @pre spec.min <= spec.max
bool at_bound(const ParamSpec& spec, double value);

}  // namespace sb
