#pragma once
// The sensor: gel geometry (flat pad, a spherical cap such as the TacTip skin, or a mesh such as the GelSight
// Mini's domed gel), its SDF, the camera, the marker layout and the output stage every model's field goes
// through. Markers live on the undeformed gel surface or markers_depth_m below it (TacTip pins), in E.
#include <optional>
#include <string>
#include <vector>

#include "core/geometry/sdf.hpp"
#include "core/sensor/camera.hpp"
#include "core/sensor/output_stage.hpp"

namespace sb {

// The sensor every dataset and scene has unless it says otherwise (tsd/1 "sensor": {"model"}).
inline constexpr const char* kDefaultSensorModel = "GelSight Mini";

struct GelSpec {
  Vec2 size_m{0.02525, 0.02075};
  double thickness_m = 0.0045;
  // "flat", "spherical_cap", or a mesh path. A mesh gel is placed so its surface apex is at z = 0 and +z
  // points out. A spherical cap is the sphere of radius_m centred at (0, 0, -radius_m) cut at the footprint
  // radius (<= radius_m), above a vertical wall down to z = -thickness_m; size_m is the footprint's box.
  std::string surface = "flat";
  double radius_m = 0.0;            // spherical_cap only
  double footprint_radius_m = 0.0;  // spherical_cap only
  // Pins below the contact surface, along its normal (0: markers on the surface).
  double markers_depth_m = 0.0;
};
// Whether `surface` names a mesh file (anything but the analytic "flat" and "spherical_cap").
bool gel_surface_is_mesh(const std::string& surface);
// The closed mesh of a spherical-cap gel (outward normals; `segments` around, `rings` from apex to rim).
// Throws std::invalid_argument for radii that do not make a cap (footprint > radius, thickness <= cap height).
TriMesh spherical_cap_mesh(const GelSpec& gel, int segments = 96, int rings = 32);

// Marker layouts. `Grid` is centred on the principal point with a square pitch; rows run along y
// (v), columns along x (u); storage is row-major with x fastest (as tsd/1 twin sets store them).
struct MarkerGrid {
  int rows = 7;  // along y
  int cols = 9;  // along x
  double pitch_px = 33.0;
};
std::vector<Vec2> marker_grid_px(const MarkerGrid& grid, const Camera& camera);
// Parses "7x9" (rows x cols). Throws InputError(where) on anything else.
MarkerGrid parse_marker_grid(const std::string& text, const std::string& where);

struct Sensor {
  Camera camera;
  GelSpec gel;
  std::vector<Vec2> markers_rest_px;
  std::vector<Vec3> p_EM;  // marker rest positions on the gel surface (over the pin, for pins at depth), in E (metres)
  SdfPtr gel_sdf;          // phi_E: negative inside the gel
  TriMesh gel_mesh;        // for display
  SensorOutputStage output_stage;  // applied to every model's field (the identity for the GelSight Mini)
};

// Builds the default GelSight Mini (flat 25.25 x 20.75 x 4.5 mm pad, 7 x 9 markers at 33 px).
Sensor make_default_sensor();
// Builds a sensor from its parts; for a mesh gel, `gel_mesh_E` is already in E (apex at z = 0). A flat gel
// (surface "flat", no mesh) gets the analytic pad SDF and a box mesh. A spherical cap gets its generated mesh
// and then goes the mesh gel's way. Markers: an orthographic camera puts them under their pixel (at the
// surface, markers_depth_m lower); a pinhole camera back-projects each markers_rest_px ray onto the pin
// surface (the plane z = -depth, or the sphere of radius R - depth about the cap's centre). The output stage is
// built from those pins; p_EM is the surface point over each pin (along the normal), where the models compute
// the field. A pinhole camera needs a flat or spherical-cap gel (std::invalid_argument for a mesh file). A mesh gel
// gets make_mesh_sdf of the mesh, markers at the mesh surface height under them, and gel.size_m / thickness_m replaced
// by the mesh's footprint and depth. Throws std::invalid_argument for a mesh surface without a mesh, and InputError
// when a marker lies outside the mesh footprint.
Sensor make_sensor(const Camera& camera, const GelSpec& gel, const std::vector<Vec2>& markers_rest_px,
                   const TriMesh* gel_mesh_E = nullptr);

// The highest and lowest crossings of the vertical line through (x, y) with a mesh (z_high = the surface
// under a marker); nullopt when the line misses the mesh. Brute force over the triangles.
struct VerticalSpan {
  double z_low = 0.0;
  double z_high = 0.0;
};
std::optional<VerticalSpan> vertical_span(const TriMesh& mesh, const Vec2& xy);

// The real GelSight Mini gel from ../shared/data/meshes/gel_gelsight_mini.obj (millimetres, thin axis y)
// placed into E: thin axis to z, domed top at z = 0.
TriMesh gelsight_mini_gel_in_E(const std::string& obj_path);

}  // namespace sb
