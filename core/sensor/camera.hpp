#pragma once
// The sensor camera of tsd/1 (FORMAT.md, docs/sensors.md). Two models:
//  - orthographic (the GelSight Mini, the default): a gel point (x, y) in E is seen at
//      u = cu + x / s,  v = cv + y / s,  s = mm_per_px * 1e-3 metres per pixel, (cu, cv) = principal_px;
//  - pinhole (the TacTip, which looks at its skin from inside): the camera centre sits distance_m = D below
//    the skin apex on the -z_E axis and looks along +z_E, so a point p_E = (x, y, z) has the normalised
//    image coordinates (xn, yn) = (x, y) / (z + D), radially distorted by (1 + k1 r^2), r^2 = xn^2 + yn^2:
//      u = cu + f (1 + k1 r^2) xn,  v = cv + f (1 + k1 r^2) yn,  f = focal_px.
//    The image axes are the E axes (as for the orthographic camera), so both models agree to first order at
//    the apex with s = D / f (metres_per_px()).
#include <Eigen/Core>
#include <optional>

#include "core/geometry/pose.hpp"

namespace sb {

enum class CameraModel { kOrthographic, kPinhole };

struct Camera {
  CameraModel model = CameraModel::kOrthographic;
  double mm_per_px = 0.0634;  // orthographic scale (unused by the pinhole model)
  Vec2 principal_px{159.5, 119.5};
  int width_px = 320;
  int height_px = 240;
  double focal_px = 0.0;    // pinhole only
  double distance_m = 0.0;  // pinhole only: camera centre below the skin apex
  double k1 = 0.0;          // pinhole only: radial distortion on normalised coordinates

  bool pinhole() const { return model == CameraModel::kPinhole; }
  // The scale of the principal ray at the apex (z = 0): mm_per_px for the orthographic camera, D / f for the
  // pinhole. The 2D maps below are the orthographic camera, or the pinhole's linearisation at the apex.
  double metres_per_px() const { return pinhole() ? distance_m / focal_px : mm_per_px * 1e-3; }
  double px_per_metre() const { return 1.0 / metres_per_px(); }
  Vec2 px_from_E(const Vec2& p_E_xy) const { return principal_px + p_E_xy / metres_per_px(); }
  Vec2 E_from_px(const Vec2& uv) const { return (uv - principal_px) * metres_per_px(); }
  // Displacements map without the offset.
  Vec2 px_displacement(const Vec2& d_E_xy) const { return d_E_xy / metres_per_px(); }
  Vec2 E_displacement(const Vec2& d_uv) const { return d_uv * metres_per_px(); }

  // The image point of p_E (3D). For the pinhole model p_E must lie in front of the camera (z > -D).
  Vec2 project(const Vec3& p_E) const;
  // d(uv)/d(p_E), the 2x3 Jacobian of project() at p_E.
  Eigen::Matrix<double, 2, 3> project_jacobian(const Vec3& p_E) const;
  // The ray through an image point: origin o_E and unit direction d_E such that project(o + t d) = uv for every
  // t > 0 (pinhole: the distortion inverted by Newton's method; orthographic: the vertical line through
  // E_from_px(uv), going down from z = 0). nullopt when the distortion cannot be inverted at uv.
  struct Ray {
    Vec3 origin_E;
    Vec3 direction_E;
  };
  std::optional<Ray> back_project(const Vec2& uv) const;
};

}  // namespace sb
