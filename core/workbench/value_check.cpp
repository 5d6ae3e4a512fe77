#include "core/workbench/value_check.hpp"

#include <cmath>
#include <cstdio>

namespace sb {

namespace {

// A length in metres as millimetres in the message ("-20 mm", "1e+09 mm").
std::string mm(double m) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g mm", m * 1e3);
  return buf;
}

std::string number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

bool pose_finite(const Pose& X) { return X.matrix().allFinite(); }

}  // namespace

PoseCheck check_indenter_pose(const Pose& X_EI, double gel_thickness_m, double reach_m) {
  if (!pose_finite(X_EI)) return {false, "the pose has a value that is not a number; kept the last pose"};
  const double z = X_EI.translation().z();
  if (z < -gel_thickness_m)
    return {false, "z = " + mm(z) + " is below the gel's back (" + mm(gel_thickness_m) + " thick); kept the last pose"};
  if (z > reach_m)
    return {false,
            "z = " + mm(z) + " is above the indenter's reach (" + mm(reach_m) + " above the gel); kept the last pose"};
  return {};
}

ParamCheck check_param_value(const ParamSpec& spec, double typed) {
  if (!std::isfinite(typed)) return {false, 0.0, spec.name + ": " + number(typed) + " is not a number; kept"};
  if (typed < spec.min)
    return {
        true, spec.min,
        spec.name + ": " + number(typed) + " is below its bound " + number(spec.min) + "; set to " + number(spec.min)};
  if (typed > spec.max)
    return {
        true, spec.max,
        spec.name + ": " + number(typed) + " is above its bound " + number(spec.max) + "; set to " + number(spec.max)};
  return {true, typed, ""};
}

bool at_bound(const ParamSpec& spec, double value) {
  if (spec.is_switch || !std::isfinite(value)) return false;
  // On a log scale "near" is a ratio: 1e5 out of [1, 1e9] is far from both bounds although tiny beside 1e9.
  const bool log = spec.log_scale && spec.min > 0 && value > 0;
  const double lo = log ? std::log(spec.min) : spec.min;
  const double hi = log ? std::log(spec.max) : spec.max;
  const double v = log ? std::log(value) : value;
  const double margin = kAtBoundRelMargin * (hi - lo);
  return v <= lo + margin || v >= hi - margin;
}

}  // namespace sb
