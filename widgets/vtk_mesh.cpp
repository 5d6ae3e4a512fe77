#include "widgets/vtk_mesh.hpp"

#include <vtkPointData.h>
#include <vtkPolyDataNormals.h>
#include <vtkProperty.h>

namespace sb::ui {

vtkSmartPointer<vtkPolyData> polydata_from_mesh(const TriMesh& mesh, bool sharp_edges) {
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

vtkSmartPointer<vtkMatrix4x4> vtk_matrix_mm(const Pose& X) {
  auto m = vtkSmartPointer<vtkMatrix4x4>::New();
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) m->SetElement(r, c, X.linear()(r, c));
    m->SetElement(r, 3, X.translation()(r) * kMmPerM);
  }
  return m;
}

PointCloud::PointCloud(double size_px) {
  colours->SetNumberOfComponents(3);
  data->SetPoints(points);
  data->SetVerts(verts);
  data->GetPointData()->SetScalars(colours);
  mapper->SetInputData(data);
  actor->SetMapper(mapper);
  actor->GetProperty()->SetPointSize(static_cast<float>(size_px));
  actor->GetProperty()->SetRenderPointsAsSpheres(true);
}

void PointCloud::clear() {
  points->Reset();
  verts->Reset();
  colours->Reset();
}

void PointCloud::add(const Vec3& p_mm, const std::array<unsigned char, 3>& rgb) {
  const vtkIdType id = points->InsertNextPoint(p_mm.x(), p_mm.y(), p_mm.z());
  verts->InsertNextCell(1, &id);
  colours->InsertNextTypedTuple(rgb.data());
}

void PointCloud::commit() {
  points->Modified();
  verts->Modified();
  colours->Modified();
  data->Modified();
}

}  // namespace sb::ui
