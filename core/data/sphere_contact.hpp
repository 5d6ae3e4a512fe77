#pragma once
// Sphere contact (centre, contact radius, travel) estimated from a marker displacement field in pixels.
#include <vector>

#include "core/geometry/pose.hpp"

namespace sb {

// Sphere contact from a marker displacement field (pixels): far-field drift = median displacement of all
// markers, removed first; centre = |d|-weighted centroid of the markers above half the peak |d|; contact
// radius a = radius of the peak mean radial displacement (for a sphere pressed into a layer the surface
// radial displacement peaks near the contact edge), uncertainty half a pitch; tangential travel = mean
// displacement of the markers inside a (the radial parts cancel by symmetry).
struct SphereContactEstimate {
  Vec2 centre_px = Vec2::Zero();
  Vec2 drift_px = Vec2::Zero();
  double a_px = 0, a_sigma_px = 0;
  Vec2 travel_px = Vec2::Zero();
  double travel_sigma_px = 0;
  int markers_inside = 0;
};
SphereContactEstimate estimate_sphere_contact(const std::vector<Vec2>& rest_px, const std::vector<Vec2>& disp_px,
                                              double pitch_px);
// The same with a given centre and contact radius (drift removed, travel = mean displacement inside a).
SphereContactEstimate estimate_sphere_contact_with_radius(const std::vector<Vec2>& rest_px,
                                                          const std::vector<Vec2>& disp_px, const Vec2& centre_px,
                                                          double a_px, double a_sigma_px);
// Spherical-cap depth d = R - sqrt(R^2 - a^2); NaN when a > R.
double sphere_depth_from_contact_radius(double R, double a);

}  // namespace sb
