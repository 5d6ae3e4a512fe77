#pragma once
// The 3D view's drag of the indenter, without a window: the mouse (where it was pressed, where it is now,
// the modifier held at the press) and the camera's ray through it, as plain numbers, to the pose X_EI the
// indenter is dragged to. widgets/viewport.cpp feeds it from ImGui and VTK; tests/test_drag_controller.cpp
// drives it with hand-made cameras.
//
// Units: mouse positions in screen pixels (y down, as ImGui's io.MousePos); rays and picked points in E in
// millimetres (the viewport's world: VTK draws in mm); poses in metres, as everywhere else.
#include <numbers>
#include <optional>

#include "core/geometry/pose.hpp"

namespace sb {

// What a left drag on the indenter does: kPlane slides it in the pad plane (under the mouse), kPush moves it
// along the pad normal, kTwist turns it about the normal, kTilt tilts (about x) and rolls (about y).
enum class DragMode { kNone, kPlane, kPush, kTwist, kTilt };

// The modifier keys held when the left button went down.
struct DragModifiers {
  bool shift = false;
  bool ctrl = false;
  bool alt = false;
};

// Shift pushes, else Ctrl twists, else Alt tilts, else the drag slides in the plane.
DragMode drag_mode_for(const DragModifiers& held);

// The camera's ray through one pixel: its points on the near and far clipping planes, in E (mm).
struct PickRay {
  Vec3 near_E_mm = Vec3::Zero();
  Vec3 far_E_mm = Vec3::Zero();
};

// Where `ray` meets the plane z = z_E_mm (E, mm). None when the ray grazes the plane (a side view): its
// direction's z is below kMinRaySlope of its length, and the hit would jump far for a pixel's move.
inline constexpr double kMinRaySlope = 0.05;
std::optional<Vec3> ray_hit_on_plane(const PickRay& ray, double z_E_mm);

class DragController {
 public:
  static constexpr double kMmPerM = 1000.0;
  // Gains: a pixel of vertical mouse motion pushes 0.01 mm; a pixel turns 0.4 degrees.
  static constexpr double kPushMmPerPx = 0.01;
  static constexpr double kTurnRadPerPx = 0.4 * std::numbers::pi / 180.0;

  // A press on the indenter at pose X_EI, on its surface point p_EP_mm (E, mm; the plane drag keeps this
  // point under the mouse), with the mouse at mouse_px. kNone starts nothing.
  void press(DragMode mode, const Pose& X_EI, const Vec3& p_EP_mm, const Vec2& mouse_px);
  void release() { mode_ = DragMode::kNone; }
  DragMode mode() const { return mode_; }
  bool active() const { return mode_ != DragMode::kNone; }

  // The pose the drag puts the indenter at with the mouse now at mouse_px; for kPlane `ray` is the camera's
  // ray through the mouse (none, or grazing the plane: the indenter stays where it was pressed). Each pose is
  // from the press pose, not from the previous frame's: the same mouse position gives the same pose.
  //   kPlane: translation += (hit - p_EP) / 1000 in x and y, hit = ray on the plane z = p_EP.z
  //   kPush:  translation.z -= dy * kPushMmPerPx / 1000         (dy > 0: mouse down, pushed in)
  //   kTwist: R = Rz(dx * kTurnRadPerPx) * R_press
  //   kTilt:  R = Ry(dx * kTurnRadPerPx) * Rx(dy * kTurnRadPerPx) * R_press
  // with (dx, dy) = mouse_px - the press's mouse position. There is no limit on the push: the model takes
  // any depth (the pose panel shows it).
  // @pre active()
  Pose pose_at(const Vec2& mouse_px, const std::optional<PickRay>& ray) const;

 private:
  DragMode mode_ = DragMode::kNone;
  Pose X_EI_at_press_ = Pose::Identity();
  Vec3 p_EP_mm_at_press_ = Vec3::Zero();
  Vec2 mouse_px_at_press_ = Vec2::Zero();
};

}  // namespace sb
