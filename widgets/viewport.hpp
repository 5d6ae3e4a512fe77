#pragma once
// The 3D view (VTK in ImGui): the elastomer pad at its real size, its top surface dented where the
// indenter is in it (core/geometry/indent.hpp), its markers coloured by |d| of one model, the indenter
// (translucent; a big one cut away above the contact) with its contact patch highlighted, and the tracked surface points
// of a model coloured by Stick / Slip / Free with lines to their anchors. VTK renders into its own
// framebuffer (vtkGenericOpenGLRenderWindow); the colour texture is shown with ImGui::Image.
//
// Mouse: left-drag on the indenter moves it in the pad plane; Shift+drag pushes it in/out; Ctrl+drag
// twists it about the pad normal; Alt+drag tilts (x) and rolls (y). Elsewhere left-drag orbits,
// middle-drag pans, right-drag and the wheel zoom (VTK's trackball camera). The drag's arithmetic, mouse to
// pose: core/workbench/drag_controller.hpp.
#include <memory>
#include <optional>

#include "core/workbench/app_state.hpp"
#include "core/workbench/frame_backdrop.hpp"
#include "core/workbench/session_file.hpp"

namespace sb::ui {

enum class CameraPreset { kIso, kTop, kSide };

class Viewport3D {
 public:
  Viewport3D();
  ~Viewport3D();
  Viewport3D(const Viewport3D&) = delete;
  Viewport3D& operator=(const Viewport3D&) = delete;

  // Builds the actors for a sensor and an indenter (call again when the scene changes).
  void set_scene(const Sensor& sensor, const Indenter& indenter);
  // Moves the indenter, dents a flat pad where the indenter is in it, and updates markers (coloured by
  // |d| up to `colour_max_px`, the field panels' scale) and tracked points from one model's output.
  void update(const AppSnapshot& snapshot, int model_index, float colour_max_px, ColourMap map);
  void set_camera(CameraPreset preset);
  // The camera as the user left it (none before the first view is framed), and back (a session reopened).
  std::optional<CameraView> camera_view() const;
  void set_camera_view(const CameraView& view);
  // Renders at `size` pixels and places the image in the current ImGui window. Returns the pose the user
  // drags the indenter to, when `interactive` and a drag is under way.
  std::optional<Pose> draw(float width, float height, const Pose& X_EI_now, bool interactive);
  bool dragging() const;
  // Something is moving (a drag, a camera gesture, a pending re-render): keep drawing frames.
  bool busy() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace sb::ui
