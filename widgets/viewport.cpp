#include "widgets/viewport.hpp"

#include <GL/glew.h>
#include <imgui.h>
#include <vtkActor.h>
#include <vtkCallbackCommand.h>
#include <vtkCamera.h>
#include <vtkCellArray.h>
#include <vtkCellPicker.h>
#include <vtkGenericOpenGLRenderWindow.h>
#include <vtkGenericRenderWindowInteractor.h>
#include <vtkInteractorStyleTrackballCamera.h>
#include <vtkLight.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkOpenGLFramebufferObject.h>
#include <vtkOpenGLState.h>
#include <vtkPlane.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkRenderer.h>
#include <vtkSmartPointer.h>
#include <vtkTransform.h>
#include <vtkUnsignedCharArray.h>

#include <algorithm>
#include <cmath>

#include "core/geometry/indent.hpp"
#include "core/workbench/drag_controller.hpp"
#include "widgets/field_panel.hpp"
#include "widgets/pad_surface.hpp"
#include "widgets/vtk_mesh.hpp"

namespace sb::ui {

namespace {
// An indenter wider than this fraction of the pad's shorter side would hide the pad: it is cut away
// above the contact (kCutHeightM above its lowest point) and the rest drawn as a faint ghost.
constexpr double kBigIndenterFraction = 0.6;
constexpr double kCutHeightM = 3.0e-3;

std::array<unsigned char, 3> rgb_of(ImU32 c) {
  return {static_cast<unsigned char>(c >> IM_COL32_R_SHIFT), static_cast<unsigned char>(c >> IM_COL32_G_SHIFT),
          static_cast<unsigned char>(c >> IM_COL32_B_SHIFT)};
}

constexpr std::array<unsigned char, 3> kMarkerRgb{25, 25, 30};
constexpr std::array<unsigned char, 3> kStickRgb{40, 190, 80};
constexpr std::array<unsigned char, 3> kSlipRgb{235, 80, 40};
constexpr std::array<unsigned char, 3> kFreeRgb{150, 150, 160};
constexpr std::array<unsigned char, 3> kAnchorRgb{60, 120, 255};
constexpr std::array<unsigned char, 3> kIndenterRgb{205, 205, 215};
constexpr std::array<unsigned char, 3> kIndenterContactRgb{255, 150, 30};

}  // namespace

struct Viewport3D::Impl {
  // VTK's pipeline: a render window on the current GL context, two layers on one camera, and the
  // trackball interactor and picker the mouse drives.
  struct Vtk {
    vtkNew<vtkGenericOpenGLRenderWindow> window;
    vtkNew<vtkRenderer> renderer;
    vtkNew<vtkRenderer> overlay;  // layer 1, same camera: tracked points drawn over the (opaque) indenter
    vtkNew<vtkGenericRenderWindowInteractor> interactor;
    vtkNew<vtkInteractorStyleTrackballCamera> style;
    vtkNew<vtkCellPicker> picker;
  };
  // What is drawn: the pad, the indenter, the markers and a model's tracked points.
  struct Actors {
    vtkNew<vtkActor> pad;  // a mesh gel (domed): drawn as its mesh, not dented
    PadSurface flat_pad;   // a flat gel: a dentable top surface and its sides
    bool flat = true;
    vtkNew<vtkActor> indenter;
    vtkNew<vtkActor> indenter_ghost;  // a big indenter above the cut, faint
    vtkNew<vtkPlane> cut_below, cut_above;
    bool big_indenter = false;
    vtkSmartPointer<vtkPolyData> indenter_data;
    vtkNew<vtkUnsignedCharArray> indenter_colours;
    PointCloud markers{7.0};
    PointCloud tracked{5.0};
    PointCloud anchors{3.0};
    vtkNew<vtkPolyData> links;
    vtkNew<vtkActor> links_actor;
  };
  // The GL texture VTK's image is copied into, shown with ImGui::Image.
  struct Target {
    GLuint fbo = 0, texture = 0;
    int width = 0, height = 0;
    bool initialised = false;
  };
  // What the texture shows. Re-render only when something changed (pose, fields, camera, size).
  struct Shown {
    const Sensor* sensor = nullptr;  // aliased from set_scene: must outlive the scene
    const Indenter* indenter_src = nullptr;
    Pose X_EI_shown = Pose::Identity();
    bool have_pose = false;
    float colour_max_px = 1.0f;
    ColourMap map = ColourMap::kViridis;
    bool camera_set = false;
    bool dirty = true;
    std::uint64_t shown_version = 0;
    int shown_model = -1;
    // While the indenter moves the 3D view renders at a lower resolution (llvmpipe's cost is per pixel);
    // the first frame it stands still is rendered at full resolution again.
    bool moving = false;
    bool low_res_shown = false;
  };
  // The mouse: a drag of the indenter (core/workbench/drag_controller.hpp) or a camera gesture.
  struct Mouse {
    DragController drag;
    bool camera_button_down[3] = {false, false, false};
  };

  Vtk vtk;
  Actors actors;
  Target target;
  Shown shown;
  Mouse mouse;

  void init_gl(int w, int h);
  void resize(int w, int h);
  void render(int w, int h);
  // The camera's ray through VTK pixel (x, y) (y down), in E (mm); none for a degenerate projection.
  std::optional<PickRay> pick_ray(double x, double y) const;
  // The mouse buttons of this frame, at VTK pixel (mx, my): pressed over the view, and released.
  void press_buttons(double mx, double my, const Pose& X_EI_now);
  void release_buttons();
};

void Viewport3D::Impl::init_gl(int w, int h) {
  vtkGenericOpenGLRenderWindow* window = vtk.window;
  window->SetMultiSamples(0);
  window->SetFrameBlitModeToNoBlit();
  window->SetReadyForRendering(true);
  window->SetIsCurrent(true);
  window->SetSupportsOpenGL(true);
  window->SetIsDirect(true);
  window->InitializeFromCurrentContext();
  window->SetOwnContext(false);
  window->SetNumberOfLayers(2);
  window->AddRenderer(vtk.renderer);
  window->AddRenderer(vtk.overlay);
  window->SetSize(w, h);
  // Light, Polyscope-like: dark markers and the translucent pad read well on it.
  vtk.renderer->SetBackground(0.62, 0.65, 0.70);
  vtk.renderer->SetBackground2(0.93, 0.94, 0.96);
  vtk.renderer->GradientBackgroundOn();
  vtk.renderer->SetBackgroundAlpha(1.0);  // or the background vanishes inside ImGui::Image
  vtk.interactor->SetRenderWindow(window);
  vtk.interactor->SetInteractorStyle(vtk.style);
  vtk.interactor->EnableRenderOff();  // we render once per ImGui frame
  vtk.interactor->SetSize(w, h);
  vtk.picker->SetTolerance(0.002);
  vtk.picker->PickFromListOn();
  vtk.picker->AddPickList(actors.indenter);

  glGenFramebuffers(1, &target.fbo);
  glGenTextures(1, &target.texture);
  target.initialised = true;
}

void Viewport3D::Impl::resize(int w, int h) {
  if (w == target.width && h == target.height) return;
  target.width = w;
  target.height = h;
  vtk.window->SetSize(w, h);
  vtk.interactor->SetSize(w, h);
  glBindTexture(GL_TEXTURE_2D, target.texture);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, w, h, 0, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glBindFramebuffer(GL_FRAMEBUFFER, target.fbo);
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, target.texture, 0);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

void Viewport3D::Impl::render(int w, int h) {
  if (!target.initialised) init_gl(w, h);
  if (w != target.width || h != target.height) shown.dirty = true;
  if (!shown.dirty) return;
  shown.dirty = false;
  resize(w, h);
  vtkGenericOpenGLRenderWindow* window = vtk.window;
  // ImGui changed GL state behind VTK's cache since the last frame.
  window->GetState()->Reset();
  window->GetState()->Push();
  window->Render();
  // Copy VTK's display framebuffer into our texture.
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, target.fbo);
  window->BlitDisplayFramebuffer();
  // Translucent geometry leaves alpha < 1 behind it, and ImGui::Image blends the texture over the
  // dark window: force alpha to 1 so what VTK drew is what is shown.
  glBindFramebuffer(GL_FRAMEBUFFER, target.fbo);
  glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_TRUE);
  glClearColor(0, 0, 0, 1);
  glClear(GL_COLOR_BUFFER_BIT);
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  window->GetState()->Pop();
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

std::optional<PickRay> Viewport3D::Impl::pick_ray(double x, double y) const {
  // Display coordinates have y up.
  const double yd = target.height - 1 - y;
  double near_w[4], far_w[4];
  vtk.renderer->SetDisplayPoint(x, yd, 0.0);
  vtk.renderer->DisplayToWorld();
  vtk.renderer->GetWorldPoint(near_w);
  vtk.renderer->SetDisplayPoint(x, yd, 1.0);
  vtk.renderer->DisplayToWorld();
  vtk.renderer->GetWorldPoint(far_w);
  if (near_w[3] == 0 || far_w[3] == 0) return std::nullopt;
  return PickRay{Vec3(near_w[0] / near_w[3], near_w[1] / near_w[3], near_w[2] / near_w[3]),
                 Vec3(far_w[0] / far_w[3], far_w[1] / far_w[3], far_w[2] / far_w[3])};
}

Viewport3D::Viewport3D() : impl_(std::make_unique<Impl>()) {
  Impl& s = *impl_;
  s.vtk.renderer->AddActor(s.actors.pad);
  s.vtk.renderer->AddActor(s.actors.flat_pad.top_actor);
  s.vtk.renderer->AddActor(s.actors.flat_pad.sides_actor);
  s.vtk.renderer->AddActor(s.actors.markers.actor);
  s.vtk.overlay->AddActor(s.actors.tracked.actor);
  s.vtk.overlay->AddActor(s.actors.anchors.actor);
  s.vtk.overlay->AddActor(s.actors.links_actor);
  s.vtk.overlay->SetLayer(1);
  s.vtk.overlay->InteractiveOff();
  s.vtk.overlay->SetActiveCamera(s.vtk.renderer->GetActiveCamera());
  s.vtk.renderer->AddActor(s.actors.indenter);
  s.vtk.renderer->AddActor(s.actors.indenter_ghost);
  vtkNew<vtkPolyDataMapper> links_mapper;
  links_mapper->SetInputData(s.actors.links);
  s.actors.links_actor->SetMapper(links_mapper);
  s.actors.links_actor->GetProperty()->SetColor(0.35, 0.55, 1.0);
  s.actors.links_actor->GetProperty()->SetLineWidth(1.5f);
  s.actors.indenter_colours->SetNumberOfComponents(3);
}

Viewport3D::~Viewport3D() {
  if (impl_->target.initialised) {
    glDeleteFramebuffers(1, &impl_->target.fbo);
    glDeleteTextures(1, &impl_->target.texture);
  }
}

bool Viewport3D::dragging() const { return impl_->mouse.drag.active(); }
bool Viewport3D::busy() const {
  const Impl& s = *impl_;
  return s.shown.dirty || s.mouse.drag.active() || s.mouse.camera_button_down[0] || s.mouse.camera_button_down[1] ||
         s.mouse.camera_button_down[2];
}

void Viewport3D::set_scene(const Sensor& sensor, const Indenter& indenter) {
  Impl& s = *impl_;
  s.shown.sensor = &sensor;
  s.shown.indenter_src = &indenter;

  // The pad: a flat gel as a top surface the indenter dents, a mesh gel (domed) as its mesh.
  s.actors.flat = sensor.gel.surface == "flat" || sensor.gel_mesh.empty();
  s.actors.pad->SetVisibility(!s.actors.flat);
  s.actors.flat_pad.top_actor->SetVisibility(s.actors.flat);
  s.actors.flat_pad.sides_actor->SetVisibility(s.actors.flat);
  if (s.actors.flat) {
    s.actors.flat_pad.build(sensor.gel.size_m, sensor.gel.thickness_m);
  } else {
    vtkNew<vtkPolyDataMapper> pad_mapper;
    s.actors.pad->GetProperty()->BackfaceCullingOff();
    pad_mapper->SetInputData(polydata_from_mesh(sensor.gel_mesh, true));
    pad_mapper->ScalarVisibilityOff();
    s.actors.pad->SetMapper(pad_mapper);
    s.actors.pad->GetProperty()->SetColor(0.95, 0.88, 0.72);
    s.actors.pad->GetProperty()->SetOpacity(0.45);
    s.actors.pad->GetProperty()->SetAmbient(0.6);
    s.actors.pad->GetProperty()->SetDiffuse(0.5);
    s.actors.pad->PickableOff();
  }

  s.actors.indenter_data = polydata_from_mesh(indenter.mesh);
  s.actors.indenter_colours->SetNumberOfTuples(s.actors.indenter_data->GetNumberOfPoints());
  for (vtkIdType i = 0; i < s.actors.indenter_data->GetNumberOfPoints(); ++i)
    s.actors.indenter_colours->SetTypedTuple(i, kIndenterRgb.data());
  s.actors.indenter_data->GetPointData()->SetScalars(s.actors.indenter_colours);
  vtkNew<vtkPolyDataMapper> ind_mapper;
  ind_mapper->SetInputData(s.actors.indenter_data);
  ind_mapper->SetColorModeToDirectScalars();
  s.actors.indenter->SetMapper(ind_mapper);
  s.actors.indenter->GetProperty()->SetSpecular(0.3);
  s.actors.indenter->GetProperty()->SetSpecularPower(20);
  // Translucent, so the dent it makes shows through it. A big indenter (the 35 mm sphere, the cow)
  // would hide the pad: only its part near the pad is drawn so, the rest as a faint ghost.
  s.actors.indenter->GetProperty()->SetOpacity(0.55);
  const Eigen::Vector3d extent = indenter.mesh.bounds().sizes();
  s.actors.big_indenter = std::max(extent.x(), extent.y()) > kBigIndenterFraction * sensor.gel.size_m.minCoeff();
  ind_mapper->RemoveAllClippingPlanes();
  vtkNew<vtkPolyDataMapper> ghost_mapper;
  ghost_mapper->SetInputData(s.actors.indenter_data);
  ghost_mapper->ScalarVisibilityOff();
  s.actors.indenter_ghost->SetMapper(ghost_mapper);
  s.actors.indenter_ghost->GetProperty()->SetColor(0.8, 0.8, 0.85);
  s.actors.indenter_ghost->GetProperty()->SetOpacity(0.12);
  s.actors.indenter_ghost->GetProperty()->BackfaceCullingOn();
  s.actors.indenter_ghost->PickableOff();
  s.actors.indenter_ghost->SetVisibility(s.actors.big_indenter);
  if (s.actors.big_indenter) {
    s.actors.cut_below->SetNormal(0, 0, -1);  // keeps z <= the cut (VTK keeps the side the normal points to)
    s.actors.cut_above->SetNormal(0, 0, 1);
    ind_mapper->AddClippingPlane(s.actors.cut_below);
    ghost_mapper->AddClippingPlane(s.actors.cut_above);
  }
  s.actors.markers.actor->PickableOff();
  s.actors.tracked.actor->PickableOff();
  s.actors.anchors.actor->PickableOff();
  s.actors.links_actor->PickableOff();
  s.shown.have_pose = false;
  s.shown.camera_set = false;
  s.shown.shown_version = 0;
  s.shown.dirty = true;
}

namespace {

// The model's tracked points coloured by state, their anchors, and a line from each anchor to its point.
void show_tracked_points(const FieldOutput* out, PointCloud& tracked, PointCloud& anchors, vtkPolyData* links) {
  tracked.clear();
  anchors.clear();
  vtkNew<vtkPoints> link_pts;
  vtkNew<vtkCellArray> link_lines;
  if (out != nullptr) {
    for (std::size_t i = 0; i < out->p_EP.size(); ++i) {
      const PointState st = i < out->point_state.size() ? out->point_state[i] : PointState::kFree;
      const auto& rgb = st == PointState::kStick ? kStickRgb : st == PointState::kSlip ? kSlipRgb : kFreeRgb;
      tracked.add(out->p_EP[i] * kMmPerM, rgb);
      if (st != PointState::kFree && i < out->anchor_EP.size()) {
        anchors.add(out->anchor_EP[i] * kMmPerM, kAnchorRgb);
        const Vec3 a = out->anchor_EP[i] * kMmPerM, b = out->p_EP[i] * kMmPerM;
        const vtkIdType ia = link_pts->InsertNextPoint(a.data());
        const vtkIdType ib = link_pts->InsertNextPoint(b.data());
        const vtkIdType ids[2] = {ia, ib};
        link_lines->InsertNextCell(2, ids);
      }
    }
  }
  tracked.commit();
  anchors.commit();
  links->SetPoints(link_pts);
  links->SetLines(link_lines);
  links->Modified();
}

}  // namespace

void Viewport3D::update(const AppSnapshot& snap, int model_index, float colour_max_px, ColourMap map) {
  Impl& s = *impl_;
  if (s.shown.sensor == nullptr) return;
  const Sensor& sensor = *s.shown.sensor;
  if (snap.version == s.shown.shown_version && model_index == s.shown.shown_model &&
      colour_max_px == s.shown.colour_max_px && map == s.shown.map) {
    if (s.shown.moving) {
      s.shown.moving = false;
      if (s.shown.low_res_shown) s.shown.dirty = true;
    }
    return;
  }
  s.shown.shown_version = snap.version;
  s.shown.shown_model = model_index;
  s.shown.colour_max_px = colour_max_px;
  s.shown.map = map;
  s.shown.dirty = true;
  const FieldOutput* out = (model_index >= 0 && model_index < static_cast<int>(snap.models.size()))
                               ? &snap.models[model_index].out
                               : nullptr;

  // Indenter pose and contact patch (vertices inside the gel), recoloured only when the pose moved.
  s.shown.moving = s.shown.have_pose && !snap.X_EI.isApprox(s.shown.X_EI_shown, 1e-12);
  if (!s.shown.moving && s.shown.low_res_shown) s.shown.dirty = true;
  if (!s.shown.have_pose || !snap.X_EI.isApprox(s.shown.X_EI_shown, 1e-12)) {
    s.actors.indenter->SetUserMatrix(vtk_matrix_mm(snap.X_EI));
    const auto& verts = s.shown.indenter_src->mesh.vertices;
    double z_min = 1e9;
    Eigen::AlignedBox2d footprint;  // where the indenter is below the surface (E, metres)
    for (std::size_t i = 0; i < verts.size(); ++i) {
      const Vec3 p_E = snap.X_EI * verts[i];
      z_min = std::min(z_min, p_E.z());
      if (p_E.z() < 0) footprint.extend(p_E.head<2>());
      const bool inside = sensor.gel_sdf ? sensor.gel_sdf->value(p_E) < 0 : p_E.z() < 0;
      s.actors.indenter_colours->SetTypedTuple(static_cast<vtkIdType>(i),
                                               inside ? kIndenterContactRgb.data() : kIndenterRgb.data());
    }
    s.actors.indenter_colours->Modified();
    if (s.actors.flat) {
      // The mesh's vertices bound the part below the surface only to within a triangle: widen by one.
      const double margin = 2.0 * std::max(s.shown.indenter_src->mesh.bounds().sizes().maxCoeff() / 64.0, 0.2e-3);
      if (!footprint.isEmpty())
        footprint = Eigen::AlignedBox2d(footprint.min().array() - margin, footprint.max().array() + margin);
      s.actors.flat_pad.indent(*s.shown.indenter_src, snap.X_EI, z_min, footprint);
    }
    if (s.actors.big_indenter) {
      s.actors.cut_below->SetOrigin(0, 0, (z_min + kCutHeightM) * kMmPerM);
      s.actors.cut_above->SetOrigin(0, 0, (z_min + kCutHeightM) * kMmPerM);
    }
    s.shown.X_EI_shown = snap.X_EI;
    s.shown.have_pose = true;
  }

  // Markers, displaced by the model's field (pixels back to metres), on the dented surface, coloured by
  // |d| on the field panels' colour scale.
  s.actors.markers.clear();
  std::vector<Vec3> marker_E(sensor.p_EM.size());
  std::vector<double> marker_px(sensor.p_EM.size(), 0.0);
  for (std::size_t m = 0; m < sensor.p_EM.size(); ++m) {
    marker_E[m] = sensor.p_EM[m];
    if (out != nullptr && m < out->disp_px.size() && out->disp_px[m].allFinite()) {
      const Vec2 d = sensor.camera.E_displacement(out->disp_px[m]);
      marker_E[m].x() += d.x();
      marker_E[m].y() += d.y();
      marker_px[m] = out->disp_px[m].norm();
    }
  }
  if (s.actors.flat && s.shown.have_pose) indent_down(*s.shown.indenter_src->sdf, snap.X_EI, marker_E);
  for (std::size_t m = 0; m < marker_E.size(); ++m) {
    Vec3 p = marker_E[m];
    // Lift a hair above the surface so the points are not hidden inside the pad.
    p.z() += 0.05e-3;
    const bool coloured = out != nullptr && !out->disp_px.empty();
    s.actors.markers.add(
        p * kMmPerM,
        coloured ? rgb_of(colour_map(s.shown.map, float(marker_px[m] / std::max(1e-6f, colour_max_px)))) : kMarkerRgb);
  }
  s.actors.markers.commit();

  show_tracked_points(out, s.actors.tracked, s.actors.anchors, s.actors.links);
}

void Viewport3D::set_camera(CameraPreset preset) {
  Impl& s = *impl_;
  vtkCamera* cam = s.vtk.renderer->GetActiveCamera();
  const double sx = s.shown.sensor ? s.shown.sensor->gel.size_m.x() * kMmPerM : 25.0;
  cam->SetFocalPoint(0, 0, 0);
  switch (preset) {
    case CameraPreset::kTop:
      cam->SetPosition(0, 0, 3 * sx);
      cam->SetViewUp(0, 1, 0);
      break;
    case CameraPreset::kSide:
      cam->SetPosition(0, -3 * sx, 0.2 * sx);
      cam->SetViewUp(0, 0, 1);
      break;
    case CameraPreset::kIso:
      cam->SetPosition(0.9 * sx, -1.6 * sx, 1.3 * sx);
      cam->SetViewUp(0, 0, 1);
      break;
  }
  cam->SetViewAngle(30);
  // Frame the pad (and room above it for the indenter) rather than the whole indenter, which may be big.
  const double sy = s.shown.sensor ? s.shown.sensor->gel.size_m.y() * kMmPerM : 21.0;
  const double bounds[6] = {-sx / 2, sx / 2, -sy / 2, sy / 2, -3.0, 4.0};
  s.vtk.renderer->ResetCamera(bounds);
  s.vtk.renderer->ResetCameraClippingRange();
  s.shown.camera_set = true;
  s.shown.dirty = true;
}

std::optional<CameraView> Viewport3D::camera_view() const {
  const Impl& s = *impl_;
  if (!s.shown.camera_set) return std::nullopt;
  vtkCamera* cam = s.vtk.renderer->GetActiveCamera();
  CameraView v;
  cam->GetPosition(v.position.data());
  cam->GetFocalPoint(v.focal_point.data());
  cam->GetViewUp(v.view_up.data());
  return v;
}

void Viewport3D::set_camera_view(const CameraView& view) {
  Impl& s = *impl_;
  if (!s.shown.camera_set) set_camera(CameraPreset::kIso);  // the view angle and framing of the presets
  vtkCamera* cam = s.vtk.renderer->GetActiveCamera();
  cam->SetPosition(view.position.data());
  cam->SetFocalPoint(view.focal_point.data());
  cam->SetViewUp(view.view_up.data());
  s.vtk.renderer->ResetCameraClippingRange();
  s.shown.camera_set = true;
  s.shown.dirty = true;
}

std::optional<Pose> Viewport3D::draw(float width, float height, const Pose& X_EI_now, bool interactive) {
  Impl& s = *impl_;
  const int w = std::max(16, static_cast<int>(width));
  const int h = std::max(16, static_cast<int>(height));
  if (!s.shown.camera_set) set_camera(CameraPreset::kIso);
  if (s.shown.dirty) {
    s.vtk.renderer->ResetCameraClippingRange();
  }
  constexpr double kMotionScale = 0.6;  // linear resolution while moving: 0.36 of the pixels
  const bool low = s.shown.moving || s.mouse.drag.active();
  if (s.shown.dirty) s.shown.low_res_shown = low;
  s.render(low ? static_cast<int>(w * kMotionScale) : w, low ? static_cast<int>(h * kMotionScale) : h);

  const ImVec2 origin = ImGui::GetCursorScreenPos();
  // VTK's texture rows start at the bottom: flip V. ImGui's texture handle is a void* that carries the GL
  // texture's name, so the integer-to-pointer cast is the API's, not an optimisation to lose.
  const std::uintptr_t texture_name = s.target.texture;
  const auto texture_id = reinterpret_cast<ImTextureID>(texture_name);  // NOLINT(performance-no-int-to-ptr)
  ImGui::Image(texture_id, ImVec2(float(w), float(h)), ImVec2(0, 1), ImVec2(1, 0));
  if (!interactive) return std::nullopt;

  const ImGuiIO& io = ImGui::GetIO();
  // Mouse in VTK's pixels (the view may be rendered at a lower resolution than it is shown).
  const double mx = (io.MousePos.x - origin.x) * s.target.width / w;
  const double my = (io.MousePos.y - origin.y) * s.target.height / h;
  s.vtk.interactor->SetEventInformationFlipY(static_cast<int>(mx), static_cast<int>(my), io.KeyCtrl, io.KeyShift);
  const bool hovered = ImGui::IsItemHovered();
  if (hovered) s.press_buttons(mx, my, X_EI_now);
  std::optional<Pose> dragged_to;
  if (s.mouse.drag.active() && ImGui::IsMouseDown(ImGuiMouseButton_Left)) {
    std::optional<PickRay> ray;
    if (s.mouse.drag.mode() == DragMode::kPlane) ray = s.pick_ray(mx, my);
    dragged_to = s.mouse.drag.pose_at(Vec2(io.MousePos.x, io.MousePos.y), ray);
  }
  s.release_buttons();
  const bool camera_moving = s.mouse.camera_button_down[0] || s.mouse.camera_button_down[1] ||
                             s.mouse.camera_button_down[2];
  if (io.MouseDelta.x != 0 || io.MouseDelta.y != 0) {
    s.vtk.interactor->InvokeEvent(vtkCommand::MouseMoveEvent, nullptr);
    if (camera_moving) s.shown.dirty = true;
  }
  if (hovered && io.MouseWheel != 0) s.shown.dirty = true;
  return dragged_to;
}

// A left press on the indenter starts a drag of it; any other press (and the wheel) goes to VTK's camera.
void Viewport3D::Impl::press_buttons(double mx, double my, const Pose& X_EI_now) {
  const ImGuiIO& io = ImGui::GetIO();
  if (ImGui::IsMouseClicked(ImGuiMouseButton_Left)) {
    vtk.picker->Pick(mx, target.height - 1 - my, 0.0, vtk.renderer);
    if (vtk.picker->GetActor() == actors.indenter.GetPointer()) {
      double p[3];
      vtk.picker->GetPickPosition(p);
      mouse.drag.press(drag_mode_for({io.KeyShift, io.KeyCtrl, io.KeyAlt}), X_EI_now, Vec3(p[0], p[1], p[2]),
                       Vec2(io.MousePos.x, io.MousePos.y));
    } else {
      vtk.interactor->InvokeEvent(vtkCommand::LeftButtonPressEvent, nullptr);
      mouse.camera_button_down[0] = true;
    }
  }
  if (ImGui::IsMouseClicked(ImGuiMouseButton_Middle)) {
    vtk.interactor->InvokeEvent(vtkCommand::MiddleButtonPressEvent, nullptr);
    mouse.camera_button_down[2] = true;
  }
  if (ImGui::IsMouseClicked(ImGuiMouseButton_Right)) {
    vtk.interactor->InvokeEvent(vtkCommand::RightButtonPressEvent, nullptr);
    mouse.camera_button_down[1] = true;
  }
  if (io.MouseWheel != 0)
    vtk.interactor->InvokeEvent(
        io.MouseWheel > 0 ? vtkCommand::MouseWheelForwardEvent : vtkCommand::MouseWheelBackwardEvent, nullptr);
}

// Releases end the drag and the camera gestures, wherever the mouse is.
void Viewport3D::Impl::release_buttons() {
  if (ImGui::IsMouseReleased(ImGuiMouseButton_Left)) {
    if (mouse.camera_button_down[0]) vtk.interactor->InvokeEvent(vtkCommand::LeftButtonReleaseEvent, nullptr);
    mouse.camera_button_down[0] = false;
    mouse.drag.release();
  }
  if (ImGui::IsMouseReleased(ImGuiMouseButton_Right) && mouse.camera_button_down[1]) {
    vtk.interactor->InvokeEvent(vtkCommand::RightButtonReleaseEvent, nullptr);
    mouse.camera_button_down[1] = false;
  }
  if (ImGui::IsMouseReleased(ImGuiMouseButton_Middle) && mouse.camera_button_down[2]) {
    vtk.interactor->InvokeEvent(vtkCommand::MiddleButtonReleaseEvent, nullptr);
    mouse.camera_button_down[2] = false;
  }
}

}  // namespace sb::ui
