#pragma once
// The sensor's output stage: what every model's field goes through before it is compared with an image.
//
// Models compute each marker's displacement in px at their own kappa scale for an in-plane displacement in E,
// as if the marker sat on the surface under an orthographic camera. For a sensor whose pins lie at a depth
// below the contact surface and/or that is seen by a perspective camera (the TacTip), this stage applies
//   (a) the depth smoothing at the pin depth (depth_smoothing.hpp, the subsurface_markers effect's kernel), then
//   (b) the perspective map: per marker the 2x2 matrix A_i = J_i T_i / s_0, where J_i is the camera's 2x3
//       projection Jacobian at the pin p_EP, T_i carries an in-plane displacement (dx, dy) onto the pin
//       surface with its length kept (on a spherical pin surface: the pole's tangent plane rotated onto the
//       pin's, tangent_frame_on_sphere; [I2; 0] on a plane),
//       and s_0 = f / (D - depth) is the scale of the principal ray where it meets the pin surface, so A = I at
//       the image centre and the models' kappa keeps its meaning.
// For the GelSight Mini (orthographic, pins on the surface) the stage is the identity and is skipped; for an
// orthographic camera A_i = I, so only (a) remains. Everything is precomputed per marker.
#include <optional>
#include <vector>

#include "core/geometry/pose.hpp"
#include "core/sensor/camera.hpp"
#include "core/sensor/depth_smoothing.hpp"

namespace sb {

// The 3x2 map of an in-plane displacement onto the tangent plane of a sphere centred at (0, 0, centre_z) at p_EP,
// length-preserving (columns orthonormal); the identity's first two columns at the pole.
Eigen::Matrix<double, 3, 2> tangent_frame_on_sphere(const Vec3& p_EP, double centre_z);

class SensorOutputStage {
 public:
  SensorOutputStage() = default;  // the identity
  // For the pins p_EP (at depth `markers_depth_m` below the surface) seen by `camera`. `pin_surface_centre_z` is the z
  // of the centre of the spherical pin surface (nullopt for a plane).
  SensorOutputStage(const Camera& camera, const std::vector<Vec3>& p_EP, double markers_depth_m,
                    std::optional<double> pin_surface_centre_z);

  bool identity() const { return !smooth_ && A_.empty(); }
  // disp_px in place; one entry per marker (std::invalid_argument otherwise), unless identity().
  void apply(std::vector<Vec2>& disp_px) const;
  // The per-marker matrices A_i (empty for an orthographic camera).
  const std::vector<Eigen::Matrix2d>& perspective_maps() const { return A_; }

 private:
  bool smooth_ = false;
  DepthSmoothingWeights weights_;
  std::vector<Eigen::Matrix2d> A_;
};

}  // namespace sb
