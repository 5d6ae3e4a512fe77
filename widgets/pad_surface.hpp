#pragma once
// The flat gel of the 3D view (widgets/viewport.cpp): its top surface a grid the indenter dents
// (core/geometry/indent.hpp), and its sides and bottom.
#include <vtkActor.h>
#include <vtkFloatArray.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>

#include <vector>

#include "core/geometry/indenter.hpp"
#include "core/geometry/pose.hpp"

namespace sb::ui {

// The flat pad drawn as a top surface grid that can be dented, and its sides and bottom (E, drawn in mm).
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

}  // namespace sb::ui
