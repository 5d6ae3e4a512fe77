#pragma once
// Small VTK pieces of the 3D view (widgets/viewport.cpp): meshes and poses into VTK's millimetres, and a
// coloured point cloud.
#include <vtkActor.h>
#include <vtkCellArray.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkSmartPointer.h>
#include <vtkUnsignedCharArray.h>

#include <array>

#include "core/geometry/mesh.hpp"
#include "core/geometry/pose.hpp"

namespace sb::ui {

// VTK works in millimetres: sub-millimetre geometry in metres upsets picking tolerances and clipping.
inline constexpr double kMmPerM = 1000.0;

// The mesh (metres) in millimetres with normals. `sharp_edges`: split normals at creases (a box pad), else
// smooth shading (curved indenters).
vtkSmartPointer<vtkPolyData> polydata_from_mesh(const TriMesh& mesh, bool sharp_edges = false);

// The pose as VTK's 4x4 matrix, its translation in millimetres.
vtkSmartPointer<vtkMatrix4x4> vtk_matrix_mm(const Pose& X);

// A point cloud with per-point RGB colours, drawn as sphere-shaded points.
struct PointCloud {
  vtkNew<vtkPolyData> data;
  vtkNew<vtkPoints> points;
  vtkNew<vtkCellArray> verts;
  vtkNew<vtkUnsignedCharArray> colours;
  vtkNew<vtkPolyDataMapper> mapper;
  vtkNew<vtkActor> actor;

  explicit PointCloud(double size_px);
  void clear();
  void add(const Vec3& p_mm, const std::array<unsigned char, 3>& rgb);
  // Marks the arrays changed, after the adds of a frame.
  void commit();
};

}  // namespace sb::ui
