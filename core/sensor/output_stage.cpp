// Depth smoothing and the per-marker perspective map applied to every model's field (output_stage.hpp).
#include "core/sensor/output_stage.hpp"

#include <stdexcept>
#include <string>

namespace sb {

// The model's in-plane displacement (dx, dy) is read as a displacement of the same length along the pin sphere:
// the pole's tangent plane rotated onto the pin's, about ez x n by the pin's polar angle. Bounded everywhere
// (|T d| = |d|), and to first order in the polar angle it is the vertical lift dz = -(x dx + y dy) / r.
Eigen::Matrix<double, 3, 2> tangent_frame_on_sphere(const Vec3& p_EP, double centre_z) {
  const Vec3 n = (p_EP - Vec3(0.0, 0.0, centre_z)).normalized();
  const Eigen::Matrix3d R = Eigen::Quaterniond::FromTwoVectors(Vec3::UnitZ(), n).toRotationMatrix();
  return R.leftCols<2>();
}

SensorOutputStage::SensorOutputStage(const Camera& camera, const std::vector<Vec3>& p_EP, double markers_depth_m,
                                     std::optional<double> pin_surface_centre_z) {
  if (markers_depth_m > 0.0) {
    smooth_ = true;
    weights_ = depth_smoothing_weights(p_EP, markers_depth_m);
  }
  if (!camera.pinhole()) return;  // orthographic: J T / s_0 = I
  const double s0 = camera.focal_px / (camera.distance_m - markers_depth_m);
  A_.reserve(p_EP.size());
  for (const Vec3& p : p_EP) {
    Eigen::Matrix<double, 3, 2> T;
    T.setZero();
    T(0, 0) = T(1, 1) = 1.0;
    if (pin_surface_centre_z) T = tangent_frame_on_sphere(p, *pin_surface_centre_z);
    A_.push_back(camera.project_jacobian(p) * T / s0);
  }
}

void SensorOutputStage::apply(std::vector<Vec2>& disp_px) const {
  if (identity()) return;
  const auto n = static_cast<Eigen::Index>(disp_px.size());
  if ((smooth_ && weights_.rows() != n) || (!A_.empty() && A_.size() != disp_px.size()))
    throw std::invalid_argument("sensor output stage: " + std::to_string(n) + " displacements for " +
                                std::to_string(smooth_ ? weights_.rows() : static_cast<Eigen::Index>(A_.size())) +
                                " markers");
  if (smooth_) disp_px = depth_smoothed(weights_, disp_px);
  for (std::size_t i = 0; i < A_.size(); ++i) disp_px[i] = A_[i] * disp_px[i];
}

}  // namespace sb
