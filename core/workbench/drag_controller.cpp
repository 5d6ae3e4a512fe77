#include "core/workbench/drag_controller.hpp"

#include <cmath>

namespace sb {

DragMode drag_mode_for(const DragModifiers& held) {
  if (held.shift) return DragMode::kPush;
  if (held.ctrl) return DragMode::kTwist;
  if (held.alt) return DragMode::kTilt;
  return DragMode::kPlane;
}

std::optional<Vec3> ray_hit_on_plane(const PickRay& ray, double z_E_mm) {
  const Vec3& a = ray.near_E_mm;
  const Vec3 d = ray.far_E_mm - a;
  if (std::abs(d.z()) < kMinRaySlope * d.norm()) return std::nullopt;
  const double t = (z_E_mm - a.z()) / d.z();
  return a + t * d;
}

void DragController::press(DragMode mode, const Pose& X_EI, const Vec3& p_EP_mm, const Vec2& mouse_px) {
  mode_ = mode;
  X_EI_at_press_ = X_EI;
  p_EP_mm_at_press_ = p_EP_mm;
  mouse_px_at_press_ = mouse_px;
}

Pose DragController::pose_at(const Vec2& mouse_px, const std::optional<PickRay>& ray) const {
  const double dx = mouse_px.x() - mouse_px_at_press_.x(), dy = mouse_px.y() - mouse_px_at_press_.y();
  Pose X = X_EI_at_press_;
  switch (mode_) {
    case DragMode::kPlane: {
      const std::optional<Vec3> hit = ray ? ray_hit_on_plane(*ray, p_EP_mm_at_press_.z()) : std::nullopt;
      if (hit) {
        const Vec3 d_mm = *hit - p_EP_mm_at_press_;
        X.translation().x() += d_mm.x() / kMmPerM;
        X.translation().y() += d_mm.y() / kMmPerM;
      }
      break;
    }
    case DragMode::kPush: X.translation().z() -= dy * kPushMmPerPx / kMmPerM; break;
    case DragMode::kTwist: X.linear() = Rz(dx * kTurnRadPerPx) * X.linear(); break;
    case DragMode::kTilt: X.linear() = Ry(dx * kTurnRadPerPx) * Rx(dy * kTurnRadPerPx) * X.linear(); break;
    case DragMode::kNone: break;
  }
  return X;
}

}  // namespace sb
