#include "widgets/pad_surface.hpp"

#include <vtkCellArray.h>
#include <vtkCubeSource.h>
#include <vtkPointData.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>

#include <algorithm>
#include <cmath>

#include "core/geometry/indent.hpp"
#include "widgets/vtk_mesh.hpp"

namespace sb::ui {

namespace {
// The flat gel's top surface is a grid of this many cells along its longer side: 0.26 mm, 97 x 80
// vertices for the GelSight Mini pad (the dent of a 4 mm sphere 1 mm deep, 5.3 mm across, spans 20).
// 128 cells cost ~2 ms more per frame on llvmpipe while dragging the cow (render --profile).
constexpr int kTopGridCells = 96;
// A dented vertex sits this far below the indenter's surface, so the indenter (drawn first, opaque or
// not) is not z-fighting with the gel where they touch.
constexpr double kDentClearanceM = 0.02e-3;
}  // namespace

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

}  // namespace sb::ui
