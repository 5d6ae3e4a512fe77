#pragma once
// The TacTip's pinhole camera and pin geometry fitted to the pins of one rest image (docs/sensors.md,
// "The TacTip's geometry fitted from the reference image").
//
// The pin pattern: one pin at the apex and concentric rings about it, ring i (i = 1, 2, ...) holding 6 i pins
// at the polar angle i * theta on the pin sphere (radius r_p = R - depth about the dome centre (0, 0, -R)),
// evenly spaced in azimuth, phi = phi0 + 2 pi k / (6 i), k = 0 .. 6i - 1 (the "circular pin pattern" of the
// public TacTip generator, github.com/chrisjford/TacTipGenerator; the reference image of raw/tactip_shear shows
// it: ring 2 holds 12 pins at one radius, where a hexagonal lattice would have 6 at 2 pitches and 6 at sqrt 3).
// Pin (i, k) sits at p_E = (r_p sin t cos phi, r_p sin t sin phi, -R + r_p cos t), t = i theta, and is seen at
// Camera::project(p_E).
//
// What one image determines: the pins' image radius is rho(i) = f g(sin t / (a + cos t)), a = (D - R) / r_p,
// g the radial distortion, so the image gives the function rho(i) and nothing else beyond the principal point
// and phi0. Its slope fixes f theta / (a + 1); its curvature fixes a combination of a and k1 (they trade at
// third order in t); the product f theta is free (the scale ambiguity between the pins' angular pitch and the
// focal length). So R and the depth are fixed, and of (f, D, k1) the options say which are fitted: the default
// fits D (through a) with f and k1 fixed.
#include <string>
#include <vector>

#include "core/sensor/camera.hpp"

namespace sb {

// A pin's place in the pattern: ring 0 is the apex pin, ring i >= 1 has slots 0 .. 6i - 1.
struct TactipPinSite {
  int ring = -1;  // -1: not assigned
  int slot = -1;
};

struct TactipRings {
  Vec2 centre_px = Vec2::Zero();       // the apex pin's image
  double azimuth_rad = 0.0;            // phi0, from ring 1
  std::vector<TactipPinSite> sites;    // one per input pin
  std::vector<double> ring_radius_px;  // mean image radius of ring i about centre_px (ring 0: 0)
  int assigned = 0;                    // pins with a site
};

// Assigns each pin its ring and slot: the apex pin is the one nearest the pins' centroid, ring 1 its six nearest
// neighbours; ring i takes the pins whose radius about the apex pin lies within half a ring spacing of the
// radius extrapolated from rings i - 1 and i - 2, and each its slot by the nearest azimuth phi0 + 2 pi k / (6 i).
// A pin off every ring, off its slot by more than a third of the slot spacing, or sharing its slot, is left
// unassigned. Throws InputError(where) for fewer than 19 pins (the apex and two full rings), no apex pin with
// six neighbours at one distance, a ring with more than 6 i pins, or fewer than three rings.
TactipRings assign_tactip_rings(const std::vector<Vec2>& pins_px, const std::string& where);

struct TactipGeometryFitOptions {
  double dome_radius_m = 0.020;  // R, fixed
  double pin_depth_m = 0.003;    // fixed: r_p = R - depth
  // Starting values of focal_px, distance_m and k1 (a pinhole camera); the fixed ones keep them. Its image size
  // is the result's; the principal point always starts at the apex pin.
  Camera initial;
  bool fit_focal = false;
  bool fit_distance = true;
  bool fit_k1 = false;
  // theta: fitted from ring 1's radius under the starting camera (fit_ring_pitch), or fixed at ring_pitch_rad
  // (a skin's printed pattern; then fit_focal lets the rings tell the focal length). phi0 and the principal
  // point are always fitted.
  bool fit_ring_pitch = true;
  double ring_pitch_rad = 0.0;  // used when !fit_ring_pitch: > 0
};

struct TactipGeometryFit {
  Camera camera;                // the fitted pinhole camera
  double ring_pitch_rad = 0.0;  // theta
  double azimuth_rad = 0.0;     // phi0
  TactipRings rings;
  int pins_used = 0;
  double rms_px = 0.0;  // reprojection residual over the pins used (sqrt of the mean squared norm)
  double max_px = 0.0;
  // One standard deviation of each fitted value from the covariance of the free parameters scaled by the
  // residual variance (sum of squares / (2 n - free parameters)); NaN for a fixed value or when the free set
  // is not identifiable (the column-scaled J^T J has a reciprocal condition number under 1e-12).
  double sigma_focal_px = 0.0, sigma_distance_m = 0.0, sigma_k1 = 0.0, sigma_pitch_rad = 0.0;
  Vec2 sigma_principal_px = Vec2::Zero();
  bool covariance_ok = false;
  double covariance_rcond = 0.0;  // reciprocal condition number of the column-scaled J^T J
  std::string termination;        // Ceres's termination type
  // The polar angle of the outermost assigned ring, i_max * theta (the pins must stay on the cap).
  double outer_ring_polar_rad() const {
    return ring_pitch_rad * double(rings.ring_radius_px.empty() ? 0 : rings.ring_radius_px.size() - 1);
  }
};

// The image of pin (ring, slot) under a camera and geometry (the model the fit inverts).
Vec2 tactip_pin_px(const Camera& camera, double dome_radius_m, double pin_depth_m, double ring_pitch_rad,
                   double azimuth_rad, const TactipPinSite& site);

// Fits the camera and the pins' polar pitch to the rest pins of one image (assign_tactip_rings, then Ceres on the
// reprojection residual of every assigned pin). Throws InputError(where) for what assign_tactip_rings refuses,
// a non-pinhole initial camera, or a fit that does not converge to finite values.
TactipGeometryFit fit_tactip_geometry(const std::vector<Vec2>& pins_px, const TactipGeometryFitOptions& options,
                                      const std::string& where);

}  // namespace sb
