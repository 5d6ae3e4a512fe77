#pragma once
// Where a rigid indenter pushes a surface down: for display (the 3D view draws the gel's top surface
// indented), not for the models. A surface point inside the indenter moves straight down (-z in E) to
// the indenter's lower surface; one outside stays. This is min(z, indenter surface below), the shape of
// a gel that takes the indenter's imprint and does nothing else.
#include <span>

#include "core/geometry/pose.hpp"
#include "core/geometry/sdf.hpp"

namespace sb {

struct IndentOptions {
  double tolerance_m = 2e-6;  // stop once this close to the indenter's surface
  int max_steps = 32;         // per point; a clamped narrow-band field (mesh SDF) needs a few more
};

// Moves each of `p_E` (points of a surface, in E) that lies inside the indenter (phi_I < 0 at
// X_EI^-1 p) down to the indenter's surface below it, in place. Sphere tracing down: a step of |phi|
// never crosses the surface, so it stops on the lower surface, not the far side. Returns how many
// points moved.
int indent_down(const Sdf& phi_I, const Pose& X_EI, std::span<Vec3> p_E, const IndentOptions& options = {});

}  // namespace sb
