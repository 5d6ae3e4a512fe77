#include "widgets/viewport.hpp"

#include <GL/glew.h>
#include <imgui.h>
#include <vtkActor.h>
#include <vtkCallbackCommand.h>
#include <vtkCamera.h>
#include <vtkCellArray.h>
#include <vtkCellPicker.h>
#include <vtkCubeSource.h>
#include <vtkFloatArray.h>
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
#include <vtkPolyDataNormals.h>
#include <vtkProperty.h>
#include <vtkRenderer.h>
#include <vtkSmartPointer.h>
#include <vtkTransform.h>
#include <vtkUnsignedCharArray.h>

#include <algorithm>
#include <cmath>

#include "core/geometry/indent.hpp"
#include "widgets/field_panel.hpp"

namespace sb::ui {

namespace {
// VTK works in millimetres: sub-millimetre geometry in metres upsets picking tolerances and clipping.
constexpr double kMmPerM = 1000.0;
// Drag gains: Shift pushes 0.01 mm per pixel, Ctrl twists and Alt tilts 0.4 degrees per pixel.
constexpr double kPushMmPerPx = 0.01;
constexpr double kTurnRadPerPx = 0.4 * M_PI / 180.0;

// `sharp_edges`: split normals at creases (a box pad), else smooth shading (curved indenters).
vtkSmartPointer<vtkPolyData> polydata_from_mesh(const TriMesh& mesh, bool sharp_edges = false) {
  vtkNew<vtkPoints> pts;
  pts->SetNumberOfPoints(static_cast<vtkIdType>(mesh.vertices.size()));
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    const Vec3 p = mesh.vertices[i] * kMmPerM;
    pts->SetPoint(static_cast<vtkIdType>(i), p.x(), p.y(), p.z());
  }
  vtkNew<vtkCellArray> tris;
  for (const auto& f : mesh.faces) {
    const vtkIdType ids[3] = {f[0], f[1], f[2]};
    tris->InsertNextCell(3, ids);
  }
  auto pd = vtkSmartPointer<vtkPolyData>::New();
  pd->SetPoints(pts);
  pd->SetPolys(tris);
  vtkNew<vtkPolyDataNormals> normals;
  normals->SetInputData(pd);
  normals->SetSplitting(sharp_edges);
  normals->SetFeatureAngle(40.0);
  normals->ConsistencyOff();
  normals->Update();
  auto out = vtkSmartPointer<vtkPolyData>::New();
  out->DeepCopy(normals->GetOutput());
  return out;
}

// A point cloud with per-point RGB colours, drawn as sphere-shaded points.
struct PointCloud {
  vtkNew<vtkPolyData> data;
  vtkNew<vtkPoints> points;
  vtkNew<vtkCellArray> verts;
  vtkNew<vtkUnsignedCharArray> colours;
  vtkNew<vtkPolyDataMapper> mapper;
  vtkNew<vtkActor> actor;

  PointCloud(double size_px) {
    colours->SetNumberOfComponents(3);
    data->SetPoints(points);
    data->SetVerts(verts);
    data->GetPointData()->SetScalars(colours);
    mapper->SetInputData(data);
    actor->SetMapper(mapper);
    actor->GetProperty()->SetPointSize(static_cast<float>(size_px));
    actor->GetProperty()->SetRenderPointsAsSpheres(true);
  }
  void clear() {
    points->Reset();
    verts->Reset();
    colours->Reset();
  }
  void add(const Vec3& p_mm, const std::array<unsigned char, 3>& rgb) {
    const vtkIdType id = points->InsertNextPoint(p_mm.x(), p_mm.y(), p_mm.z());
    verts->InsertNextCell(1, &id);
    colours->InsertNextTypedTuple(rgb.data());
  }
  void commit() {
    points->Modified();
    verts->Modified();
    colours->Modified();
    data->Modified();
  }
};

vtkSmartPointer<vtkMatrix4x4> vtk_matrix_mm(const Pose& X) {
  auto m = vtkSmartPointer<vtkMatrix4x4>::New();
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) m->SetElement(r, c, X.linear()(r, c));
    m->SetElement(r, 3, X.translation()(r) * kMmPerM);
  }
  return m;
}

// The flat gel's top surface is a grid of this many cells along its longer side: 0.26 mm, 97 x 80
// vertices for the GelSight Mini pad (the dent of a 4 mm sphere 1 mm deep, 5.3 mm across, spans 20).
// 128 cells cost ~2 ms more per frame on llvmpipe while dragging the cow (render --profile).
constexpr int kTopGridCells = 96;
// A dented vertex sits this far below the indenter's surface, so the indenter (drawn first, opaque or
// not) is not z-fighting with the gel where they touch.
constexpr double kDentClearanceM = 0.02e-3;
// An indenter wider than this fraction of the pad's shorter side would hide the pad: it is cut away
// above the contact (kCutHeightM above its lowest point) and the rest drawn as a faint ghost.
constexpr double kBigIndenterFraction = 0.6;
constexpr double kCutHeightM = 3.0e-3;

std::array<unsigned char, 3> rgb_of(ImU32 c) {
  return {static_cast<unsigned char>(c >> IM_COL32_R_SHIFT), static_cast<unsigned char>(c >> IM_COL32_G_SHIFT),
          static_cast<unsigned char>(c >> IM_COL32_B_SHIFT)};
}

// The flat pad drawn as a top surface grid that can be dented, and its sides and bottom.
struct PadSurface {
  int nx = 0, ny = 0;
  std::vector<Vec3> rest_E;  // grid vertices, z = 0 (metres)
  std::vector<Vec3> now_E;   // with the dent
  vtkNew<vtkPolyData> top;
  vtkNew<vtkPoints> points;
  vtkNew<vtkFloatArray> normals;
  vtkNew<vtkActor> top_actor;
  vtkNew<vtkActor> sides_actor;
  bool dented = false;

  void build(const Vec2& size_m, double thickness_m);
  // Dents the grid where the indenter is below the surface; cheap when it is not (nothing to redo).
  void indent(const Indenter& indenter, const Pose& X_EI, double z_min_E, const Eigen::AlignedBox2d& footprint_E);
  void upload();
};

void PadSurface::build(const Vec2& size_m, double thickness_m) {
  const double cell = std::max(size_m.x(), size_m.y()) / kTopGridCells;
  nx = static_cast<int>(std::ceil(size_m.x() / cell)) + 1;
  ny = static_cast<int>(std::ceil(size_m.y() / cell)) + 1;
  rest_E.resize(static_cast<std::size_t>(nx) * ny);
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i)
      rest_E[j * nx + i] =
          Vec3(size_m.x() * (double(i) / (nx - 1) - 0.5), size_m.y() * (double(j) / (ny - 1) - 0.5), 0);
  now_E = rest_E;
  vtkNew<vtkCellArray> quads;
  for (int j = 0; j + 1 < ny; ++j)
    for (int i = 0; i + 1 < nx; ++i) {
      const vtkIdType a = j * nx + i;
      const vtkIdType ids[4] = {a, a + 1, a + 1 + nx, a + nx};
      quads->InsertNextCell(4, ids);
    }
  points->SetNumberOfPoints(static_cast<vtkIdType>(rest_E.size()));
  normals->SetNumberOfComponents(3);
  normals->SetNumberOfTuples(static_cast<vtkIdType>(rest_E.size()));
  top->SetPoints(points);
  top->SetPolys(quads);
  top->GetPointData()->SetNormals(normals);
  dented = true;  // upload the flat state once
  upload();
  dented = false;
  vtkNew<vtkPolyDataMapper> top_mapper;
  top_mapper->SetInputData(top);
  top_mapper->ScalarVisibilityOff();
  top_actor->SetMapper(top_mapper);

  // Sides and bottom: the box without its top face (flat normals, near faces only).
  vtkNew<vtkCubeSource> box;
  const double sx = size_m.x() * kMmPerM, sy = size_m.y() * kMmPerM, t = thickness_m * kMmPerM;
  box->SetBounds(-sx / 2, sx / 2, -sy / 2, sy / 2, -t, 0.0);
  box->Update();
  vtkNew<vtkPolyData> sides;
  sides->DeepCopy(box->GetOutput());
  vtkNew<vtkCellArray> kept;
  vtkCellArray* faces = sides->GetPolys();
  faces->InitTraversal();
  vtkIdType n;
  const vtkIdType* ids;
  while (faces->GetNextCell(n, ids)) {
    bool on_top = true;
    for (vtkIdType k = 0; k < n; ++k) on_top = on_top && sides->GetPoint(ids[k])[2] > -1e-9;
    if (!on_top) kept->InsertNextCell(n, ids);
  }
  sides->SetPolys(kept);
  vtkNew<vtkPolyDataMapper> sides_mapper;
  sides_mapper->SetInputData(sides);
  sides_mapper->ScalarVisibilityOff();
  sides_actor->SetMapper(sides_mapper);
  sides_actor->GetProperty()->BackfaceCullingOn();
  for (vtkActor* a : {top_actor.GetPointer(), sides_actor.GetPointer()}) {
    a->GetProperty()->SetColor(0.95, 0.88, 0.72);
    a->GetProperty()->SetAmbient(0.45);
    a->GetProperty()->SetDiffuse(0.65);
    a->PickableOff();
  }
  top_actor->GetProperty()->SetOpacity(1.0);  // opaque: the dent is shaded, and nothing is under it to see
  sides_actor->GetProperty()->SetOpacity(0.45);
}

void PadSurface::indent(const Indenter& indenter, const Pose& X_EI, double z_min_E,
                        const Eigen::AlignedBox2d& footprint_E) {
  if (z_min_E >= 0 && !dented) return;  // not touching, and nothing to undo
  now_E = rest_E;
  dented = z_min_E < 0;
  if (dented) {
    // Only the grid under the part of the indenter below the surface can move.
    std::vector<std::size_t> idx;
    std::vector<Vec3> q;
    for (std::size_t k = 0; k < rest_E.size(); ++k)
      if (footprint_E.contains(rest_E[k].head<2>())) idx.push_back(k), q.push_back(rest_E[k]);
    indent_down(*indenter.sdf, X_EI, q);
    for (std::size_t k = 0; k < idx.size(); ++k) now_E[idx[k]].z() = q[k].z() < 0 ? q[k].z() - kDentClearanceM : 0.0;
  }
  upload();
  dented = z_min_E < 0;
}

void PadSurface::upload() {
  const auto at = [&](int i, int j) { return now_E[std::clamp(j, 0, ny - 1) * nx + std::clamp(i, 0, nx - 1)]; };
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const Vec3& p = now_E[j * nx + i];
      points->SetPoint(j * nx + i, p.x() * kMmPerM, p.y() * kMmPerM, p.z() * kMmPerM);
      // Normal from central differences of the height.
      const Vec3 dx = at(i + 1, j) - at(i - 1, j), dy = at(i, j + 1) - at(i, j - 1);
      const Vec3 n = dx.cross(dy).normalized();
      normals->SetTuple3(j * nx + i, n.x(), n.y(), n.z());
    }
  points->Modified();
  normals->Modified();
  top->Modified();
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
  vtkNew<vtkGenericOpenGLRenderWindow> window;
  vtkNew<vtkRenderer> renderer;
  vtkNew<vtkRenderer> overlay;  // layer 1, same camera: tracked points drawn over the (opaque) indenter
  vtkNew<vtkGenericRenderWindowInteractor> interactor;
  vtkNew<vtkInteractorStyleTrackballCamera> style;
  vtkNew<vtkCellPicker> picker;

  vtkNew<vtkActor> pad;  // a mesh gel (domed): drawn as its mesh, not dented
  PadSurface flat_pad;   // a flat gel: a dentable top surface and its sides
  bool flat = true;
  vtkNew<vtkActor> indenter;
  vtkNew<vtkActor> indenter_ghost;  // a big indenter above the cut, faint
  vtkNew<vtkPlane> cut_below, cut_above;
  bool big_indenter = false;
  float colour_max_px = 1.0f;
  vtkSmartPointer<vtkPolyData> indenter_data;
  vtkNew<vtkUnsignedCharArray> indenter_colours;
  PointCloud markers{7.0};
  PointCloud tracked{5.0};
  PointCloud anchors{3.0};
  vtkNew<vtkPolyData> links;
  vtkNew<vtkActor> links_actor;

  const Sensor* sensor = nullptr;
  const Indenter* indenter_src = nullptr;
  Pose X_EI_shown = Pose::Identity();
  bool have_pose = false;

  GLuint fbo = 0, texture = 0;
  int width = 0, height = 0;
  bool initialised = false;
  bool camera_set = false;
  // Re-render only when something changed (pose, fields, camera, size): the texture is kept otherwise.
  bool dirty = true;
  std::uint64_t shown_version = 0;
  int shown_model = -1;
  // While the indenter moves the 3D view renders at a lower resolution (llvmpipe's cost is per pixel);
  // the first frame it stands still is rendered at full resolution again.
  bool moving = false;
  bool low_res_shown = false;

  // Drag state
  enum class DragMode { None, Plane, Push, Twist, Tilt };
  DragMode drag = DragMode::None;
  Pose X_EI_at_press = Pose::Identity();
  Vec3 p_pick_mm = Vec3::Zero();
  ImVec2 mouse_at_press;
  bool camera_button_down[3] = {false, false, false};

  void init_gl(int w, int h);
  void resize(int w, int h);
  void render(int w, int h);
  bool ray_plane(double x, double y, double z_plane, Vec3* hit) const;
};

void Viewport3D::Impl::init_gl(int w, int h) {
  window->SetMultiSamples(0);
  window->SetFrameBlitModeToNoBlit();
  window->SetReadyForRendering(true);
  window->SetIsCurrent(true);
  window->SetSupportsOpenGL(true);
  window->SetIsDirect(true);
  window->InitializeFromCurrentContext();
  window->SetOwnContext(false);
  window->SetNumberOfLayers(2);
  window->AddRenderer(renderer);
  window->AddRenderer(overlay);
  window->SetSize(w, h);
  // Light, Polyscope-like: dark markers and the translucent pad read well on it.
  renderer->SetBackground(0.62, 0.65, 0.70);
  renderer->SetBackground2(0.93, 0.94, 0.96);
  renderer->GradientBackgroundOn();
  renderer->SetBackgroundAlpha(1.0);  // or the background vanishes inside ImGui::Image
  interactor->SetRenderWindow(window);
  interactor->SetInteractorStyle(style);
  interactor->EnableRenderOff();  // we render once per ImGui frame
  interactor->SetSize(w, h);
  picker->SetTolerance(0.002);
  picker->PickFromListOn();
  picker->AddPickList(indenter);

  glGenFramebuffers(1, &fbo);
  glGenTextures(1, &texture);
  initialised = true;
}

void Viewport3D::Impl::resize(int w, int h) {
  if (w == width && h == height) return;
  width = w;
  height = h;
  window->SetSize(w, h);
  interactor->SetSize(w, h);
  glBindTexture(GL_TEXTURE_2D, texture);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, w, h, 0, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glBindFramebuffer(GL_FRAMEBUFFER, fbo);
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, texture, 0);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

void Viewport3D::Impl::render(int w, int h) {
  if (!initialised) init_gl(w, h);
  if (w != width || h != height) dirty = true;
  if (!dirty) return;
  dirty = false;
  resize(w, h);
  // ImGui changed GL state behind VTK's cache since the last frame.
  window->GetState()->Reset();
  window->GetState()->Push();
  window->Render();
  // Copy VTK's display framebuffer into our texture.
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, fbo);
  window->BlitDisplayFramebuffer();
  // Translucent geometry leaves alpha < 1 behind it, and ImGui::Image blends the texture over the
  // dark window: force alpha to 1 so what VTK drew is what is shown.
  glBindFramebuffer(GL_FRAMEBUFFER, fbo);
  glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_TRUE);
  glClearColor(0, 0, 0, 1);
  glClear(GL_COLOR_BUFFER_BIT);
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  window->GetState()->Pop();
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

bool Viewport3D::Impl::ray_plane(double x, double y, double z_plane, Vec3* hit) const {
  // Display coordinates have y up.
  const double yd = height - 1 - y;
  double near_w[4], far_w[4];
  renderer->SetDisplayPoint(x, yd, 0.0);
  renderer->DisplayToWorld();
  renderer->GetWorldPoint(near_w);
  renderer->SetDisplayPoint(x, yd, 1.0);
  renderer->DisplayToWorld();
  renderer->GetWorldPoint(far_w);
  if (near_w[3] == 0 || far_w[3] == 0) return false;
  const Vec3 a(near_w[0] / near_w[3], near_w[1] / near_w[3], near_w[2] / near_w[3]);
  const Vec3 b(far_w[0] / far_w[3], far_w[1] / far_w[3], far_w[2] / far_w[3]);
  const Vec3 d = b - a;
  // A ray grazing the pad plane (side view) gives no stable hit.
  constexpr double kMinSlope = 0.05;
  if (std::abs(d.z()) < kMinSlope * d.norm()) return false;
  const double t = (z_plane - a.z()) / d.z();
  *hit = a + t * d;
  return true;
}

Viewport3D::Viewport3D() : impl_(std::make_unique<Impl>()) {
  Impl& s = *impl_;
  s.renderer->AddActor(s.pad);
  s.renderer->AddActor(s.flat_pad.top_actor);
  s.renderer->AddActor(s.flat_pad.sides_actor);
  s.renderer->AddActor(s.markers.actor);
  s.overlay->AddActor(s.tracked.actor);
  s.overlay->AddActor(s.anchors.actor);
  s.overlay->AddActor(s.links_actor);
  s.overlay->SetLayer(1);
  s.overlay->InteractiveOff();
  s.overlay->SetActiveCamera(s.renderer->GetActiveCamera());
  s.renderer->AddActor(s.indenter);
  s.renderer->AddActor(s.indenter_ghost);
  vtkNew<vtkPolyDataMapper> links_mapper;
  links_mapper->SetInputData(s.links);
  s.links_actor->SetMapper(links_mapper);
  s.links_actor->GetProperty()->SetColor(0.35, 0.55, 1.0);
  s.links_actor->GetProperty()->SetLineWidth(1.5f);
  s.indenter_colours->SetNumberOfComponents(3);
}

Viewport3D::~Viewport3D() {
  if (impl_->initialised) {
    glDeleteFramebuffers(1, &impl_->fbo);
    glDeleteTextures(1, &impl_->texture);
  }
}

bool Viewport3D::dragging() const { return impl_->drag != Impl::DragMode::None; }
bool Viewport3D::busy() const {
  const Impl& s = *impl_;
  return s.dirty || s.drag != Impl::DragMode::None || s.camera_button_down[0] || s.camera_button_down[1] ||
         s.camera_button_down[2];
}

void Viewport3D::set_scene(const Sensor& sensor, const Indenter& indenter) {
  Impl& s = *impl_;
  s.sensor = &sensor;
  s.indenter_src = &indenter;

  // The pad: a flat gel as a top surface the indenter dents, a mesh gel (domed) as its mesh.
  s.flat = sensor.gel.surface == "flat" || sensor.gel_mesh.empty();
  s.pad->SetVisibility(!s.flat);
  s.flat_pad.top_actor->SetVisibility(s.flat);
  s.flat_pad.sides_actor->SetVisibility(s.flat);
  if (s.flat) {
    s.flat_pad.build(sensor.gel.size_m, sensor.gel.thickness_m);
  } else {
    vtkNew<vtkPolyDataMapper> pad_mapper;
    s.pad->GetProperty()->BackfaceCullingOff();
    pad_mapper->SetInputData(polydata_from_mesh(sensor.gel_mesh, true));
    pad_mapper->ScalarVisibilityOff();
    s.pad->SetMapper(pad_mapper);
    s.pad->GetProperty()->SetColor(0.95, 0.88, 0.72);
    s.pad->GetProperty()->SetOpacity(0.45);
    s.pad->GetProperty()->SetAmbient(0.6);
    s.pad->GetProperty()->SetDiffuse(0.5);
    s.pad->PickableOff();
  }

  s.indenter_data = polydata_from_mesh(indenter.mesh);
  s.indenter_colours->SetNumberOfTuples(s.indenter_data->GetNumberOfPoints());
  for (vtkIdType i = 0; i < s.indenter_data->GetNumberOfPoints(); ++i)
    s.indenter_colours->SetTypedTuple(i, kIndenterRgb.data());
  s.indenter_data->GetPointData()->SetScalars(s.indenter_colours);
  vtkNew<vtkPolyDataMapper> ind_mapper;
  ind_mapper->SetInputData(s.indenter_data);
  ind_mapper->SetColorModeToDirectScalars();
  s.indenter->SetMapper(ind_mapper);
  s.indenter->GetProperty()->SetSpecular(0.3);
  s.indenter->GetProperty()->SetSpecularPower(20);
  // Translucent, so the dent it makes shows through it. A big indenter (the 35 mm sphere, the cow)
  // would hide the pad: only its part near the pad is drawn so, the rest as a faint ghost.
  s.indenter->GetProperty()->SetOpacity(0.55);
  const Eigen::Vector3d extent = indenter.mesh.bounds().sizes();
  s.big_indenter = std::max(extent.x(), extent.y()) > kBigIndenterFraction * sensor.gel.size_m.minCoeff();
  ind_mapper->RemoveAllClippingPlanes();
  vtkNew<vtkPolyDataMapper> ghost_mapper;
  ghost_mapper->SetInputData(s.indenter_data);
  ghost_mapper->ScalarVisibilityOff();
  s.indenter_ghost->SetMapper(ghost_mapper);
  s.indenter_ghost->GetProperty()->SetColor(0.8, 0.8, 0.85);
  s.indenter_ghost->GetProperty()->SetOpacity(0.12);
  s.indenter_ghost->GetProperty()->BackfaceCullingOn();
  s.indenter_ghost->PickableOff();
  s.indenter_ghost->SetVisibility(s.big_indenter);
  if (s.big_indenter) {
    s.cut_below->SetNormal(0, 0, -1);  // keeps z <= the cut (VTK keeps the side the normal points to)
    s.cut_above->SetNormal(0, 0, 1);
    ind_mapper->AddClippingPlane(s.cut_below);
    ghost_mapper->AddClippingPlane(s.cut_above);
  }
  s.markers.actor->PickableOff();
  s.tracked.actor->PickableOff();
  s.anchors.actor->PickableOff();
  s.links_actor->PickableOff();
  s.have_pose = false;
  s.camera_set = false;
  s.shown_version = 0;
  s.dirty = true;
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
      const PointState st = i < out->point_state.size() ? out->point_state[i] : PointState::Free;
      const auto& rgb = st == PointState::Stick ? kStickRgb : st == PointState::Slip ? kSlipRgb : kFreeRgb;
      tracked.add(out->p_EP[i] * kMmPerM, rgb);
      if (st != PointState::Free && i < out->anchor_EP.size()) {
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

void Viewport3D::update(const AppSnapshot& snap, int model_index, float colour_max_px) {
  Impl& s = *impl_;
  if (s.sensor == nullptr) return;
  const Sensor& sensor = *s.sensor;
  if (snap.version == s.shown_version && model_index == s.shown_model && colour_max_px == s.colour_max_px) {
    if (s.moving) {
      s.moving = false;
      if (s.low_res_shown) s.dirty = true;
    }
    return;
  }
  s.shown_version = snap.version;
  s.shown_model = model_index;
  s.colour_max_px = colour_max_px;
  s.dirty = true;
  const FieldOutput* out = (model_index >= 0 && model_index < static_cast<int>(snap.models.size()))
                               ? &snap.models[model_index].out
                               : nullptr;

  // Indenter pose and contact patch (vertices inside the gel), recoloured only when the pose moved.
  s.moving = s.have_pose && !snap.X_EI.isApprox(s.X_EI_shown, 1e-12);
  if (!s.moving && s.low_res_shown) s.dirty = true;
  if (!s.have_pose || !snap.X_EI.isApprox(s.X_EI_shown, 1e-12)) {
    s.indenter->SetUserMatrix(vtk_matrix_mm(snap.X_EI));
    const auto& verts = s.indenter_src->mesh.vertices;
    double z_min = 1e9;
    Eigen::AlignedBox2d footprint;  // where the indenter is below the surface (E, metres)
    for (std::size_t i = 0; i < verts.size(); ++i) {
      const Vec3 p_E = snap.X_EI * verts[i];
      z_min = std::min(z_min, p_E.z());
      if (p_E.z() < 0) footprint.extend(p_E.head<2>());
      const bool inside = sensor.gel_sdf ? sensor.gel_sdf->value(p_E) < 0 : p_E.z() < 0;
      s.indenter_colours->SetTypedTuple(static_cast<vtkIdType>(i),
                                        inside ? kIndenterContactRgb.data() : kIndenterRgb.data());
    }
    s.indenter_colours->Modified();
    if (s.flat) {
      // The mesh's vertices bound the part below the surface only to within a triangle: widen by one.
      const double margin = 2.0 * std::max(s.indenter_src->mesh.bounds().sizes().maxCoeff() / 64.0, 0.2e-3);
      if (!footprint.isEmpty())
        footprint = Eigen::AlignedBox2d(footprint.min().array() - margin, footprint.max().array() + margin);
      s.flat_pad.indent(*s.indenter_src, snap.X_EI, z_min, footprint);
    }
    if (s.big_indenter) {
      s.cut_below->SetOrigin(0, 0, (z_min + kCutHeightM) * kMmPerM);
      s.cut_above->SetOrigin(0, 0, (z_min + kCutHeightM) * kMmPerM);
    }
    s.X_EI_shown = snap.X_EI;
    s.have_pose = true;
  }

  // Markers, displaced by the model's field (pixels back to metres), on the dented surface, coloured by
  // |d| on the field panels' colour scale.
  s.markers.clear();
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
  if (s.flat && s.have_pose) indent_down(*s.indenter_src->sdf, snap.X_EI, marker_E);
  for (std::size_t m = 0; m < marker_E.size(); ++m) {
    Vec3 p = marker_E[m];
    // Lift a hair above the surface so the points are not hidden inside the pad.
    p.z() += 0.05e-3;
    const bool coloured = out != nullptr && !out->disp_px.empty();
    s.markers.add(p * kMmPerM,
                  coloured ? rgb_of(colour_map(float(marker_px[m] / std::max(1e-6f, colour_max_px)))) : kMarkerRgb);
  }
  s.markers.commit();

  show_tracked_points(out, s.tracked, s.anchors, s.links);
}

void Viewport3D::set_camera(CameraPreset preset) {
  Impl& s = *impl_;
  vtkCamera* cam = s.renderer->GetActiveCamera();
  const double sx = s.sensor ? s.sensor->gel.size_m.x() * kMmPerM : 25.0;
  cam->SetFocalPoint(0, 0, 0);
  switch (preset) {
    case CameraPreset::Top:
      cam->SetPosition(0, 0, 3 * sx);
      cam->SetViewUp(0, 1, 0);
      break;
    case CameraPreset::Side:
      cam->SetPosition(0, -3 * sx, 0.2 * sx);
      cam->SetViewUp(0, 0, 1);
      break;
    case CameraPreset::Iso:
      cam->SetPosition(0.9 * sx, -1.6 * sx, 1.3 * sx);
      cam->SetViewUp(0, 0, 1);
      break;
  }
  cam->SetViewAngle(30);
  // Frame the pad (and room above it for the indenter) rather than the whole indenter, which may be big.
  const double sy = s.sensor ? s.sensor->gel.size_m.y() * kMmPerM : 21.0;
  const double bounds[6] = {-sx / 2, sx / 2, -sy / 2, sy / 2, -3.0, 4.0};
  s.renderer->ResetCamera(bounds);
  s.renderer->ResetCameraClippingRange();
  s.camera_set = true;
  s.dirty = true;
}

std::optional<CameraView> Viewport3D::camera_view() const {
  const Impl& s = *impl_;
  if (!s.camera_set) return std::nullopt;
  vtkCamera* cam = s.renderer->GetActiveCamera();
  CameraView v;
  cam->GetPosition(v.position.data());
  cam->GetFocalPoint(v.focal_point.data());
  cam->GetViewUp(v.view_up.data());
  return v;
}

void Viewport3D::set_camera_view(const CameraView& view) {
  Impl& s = *impl_;
  if (!s.camera_set) set_camera(CameraPreset::Iso);  // the view angle and framing of the presets
  vtkCamera* cam = s.renderer->GetActiveCamera();
  cam->SetPosition(view.position.data());
  cam->SetFocalPoint(view.focal_point.data());
  cam->SetViewUp(view.view_up.data());
  s.renderer->ResetCameraClippingRange();
  s.camera_set = true;
  s.dirty = true;
}

std::optional<Pose> Viewport3D::draw(float width, float height, const Pose& X_EI_now, bool interactive) {
  Impl& s = *impl_;
  const int w = std::max(16, static_cast<int>(width));
  const int h = std::max(16, static_cast<int>(height));
  if (!s.camera_set) set_camera(CameraPreset::Iso);
  if (s.dirty) {
    s.renderer->ResetCameraClippingRange();
  }
  constexpr double kMotionScale = 0.6;  // linear resolution while moving: 0.36 of the pixels
  const bool low = s.moving || s.drag != Impl::DragMode::None;
  if (s.dirty) s.low_res_shown = low;
  s.render(low ? static_cast<int>(w * kMotionScale) : w, low ? static_cast<int>(h * kMotionScale) : h);

  const ImVec2 origin = ImGui::GetCursorScreenPos();
  // VTK's texture rows start at the bottom: flip V. ImGui's texture handle is a void* that carries the GL
  // texture's name, so the integer-to-pointer cast is the API's, not an optimisation to lose.
  const auto texture_id =
      reinterpret_cast<ImTextureID>(static_cast<std::uintptr_t>(s.texture));  // NOLINT(performance-no-int-to-ptr)
  ImGui::Image(texture_id, ImVec2(float(w), float(h)), ImVec2(0, 1), ImVec2(1, 0));
  if (!interactive) return std::nullopt;

  ImGuiIO& io = ImGui::GetIO();
  const bool hovered = ImGui::IsItemHovered();
  // Mouse in VTK's pixels (the view may be rendered at a lower resolution than it is shown).
  const double mx = (io.MousePos.x - origin.x) * s.width / w, my = (io.MousePos.y - origin.y) * s.height / h;
  s.interactor->SetEventInformationFlipY(static_cast<int>(mx), static_cast<int>(my), io.KeyCtrl, io.KeyShift);
  std::optional<Pose> target;

  using Mode = Impl::DragMode;
  if (hovered && ImGui::IsMouseClicked(ImGuiMouseButton_Left)) {
    s.picker->Pick(mx, s.height - 1 - my, 0.0, s.renderer);
    if (s.picker->GetActor() == s.indenter.GetPointer()) {
      double p[3];
      s.picker->GetPickPosition(p);
      s.p_pick_mm = Vec3(p[0], p[1], p[2]);
      s.X_EI_at_press = X_EI_now;
      s.mouse_at_press = io.MousePos;
      s.drag = io.KeyShift ? Mode::Push : io.KeyCtrl ? Mode::Twist : io.KeyAlt ? Mode::Tilt : Mode::Plane;
    } else {
      s.interactor->InvokeEvent(vtkCommand::LeftButtonPressEvent, nullptr);
      s.camera_button_down[0] = true;
    }
  }
  if (hovered && ImGui::IsMouseClicked(ImGuiMouseButton_Middle)) {
    s.interactor->InvokeEvent(vtkCommand::MiddleButtonPressEvent, nullptr);
    s.camera_button_down[2] = true;
  }
  if (hovered && ImGui::IsMouseClicked(ImGuiMouseButton_Right)) {
    s.interactor->InvokeEvent(vtkCommand::RightButtonPressEvent, nullptr);
    s.camera_button_down[1] = true;
  }
  if (hovered && io.MouseWheel != 0)
    s.interactor->InvokeEvent(
        io.MouseWheel > 0 ? vtkCommand::MouseWheelForwardEvent : vtkCommand::MouseWheelBackwardEvent, nullptr);

  if (s.drag != Mode::None && ImGui::IsMouseDown(ImGuiMouseButton_Left)) {
    const double dx = io.MousePos.x - s.mouse_at_press.x, dy = io.MousePos.y - s.mouse_at_press.y;
    Pose X = s.X_EI_at_press;
    switch (s.drag) {
      case Mode::Plane: {
        Vec3 hit;
        if (s.ray_plane(mx, my, s.p_pick_mm.z(), &hit)) {
          const Vec3 d_mm = hit - s.p_pick_mm;
          X.translation().x() += d_mm.x() / kMmPerM;
          X.translation().y() += d_mm.y() / kMmPerM;
        }
        break;
      }
      case Mode::Push: X.translation().z() -= dy * kPushMmPerPx / kMmPerM; break;
      case Mode::Twist: X.linear() = Rz(dx * kTurnRadPerPx) * X.linear(); break;
      case Mode::Tilt: X.linear() = Ry(dx * kTurnRadPerPx) * Rx(dy * kTurnRadPerPx) * X.linear(); break;
      case Mode::None: break;
    }
    target = X;
  }
  if (ImGui::IsMouseReleased(ImGuiMouseButton_Left)) {
    if (s.camera_button_down[0]) s.interactor->InvokeEvent(vtkCommand::LeftButtonReleaseEvent, nullptr);
    s.camera_button_down[0] = false;
    s.drag = Mode::None;
  }
  if (ImGui::IsMouseReleased(ImGuiMouseButton_Right) && s.camera_button_down[1]) {
    s.interactor->InvokeEvent(vtkCommand::RightButtonReleaseEvent, nullptr);
    s.camera_button_down[1] = false;
  }
  if (ImGui::IsMouseReleased(ImGuiMouseButton_Middle) && s.camera_button_down[2]) {
    s.interactor->InvokeEvent(vtkCommand::MiddleButtonReleaseEvent, nullptr);
    s.camera_button_down[2] = false;
  }
  const bool camera_moving = s.camera_button_down[0] || s.camera_button_down[1] || s.camera_button_down[2];
  if (io.MouseDelta.x != 0 || io.MouseDelta.y != 0) {
    s.interactor->InvokeEvent(vtkCommand::MouseMoveEvent, nullptr);
    if (camera_moving) s.dirty = true;
  }
  if (hovered && io.MouseWheel != 0) s.dirty = true;
  return target;
}

}  // namespace sb::ui
