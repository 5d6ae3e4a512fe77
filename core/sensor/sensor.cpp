// The GelSight Mini elastomer: marker layout, gel geometry and SDF, and the real domed gel placed into E.
#include "core/sensor/sensor.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <regex>
#include <sstream>
#include <stdexcept>

#include "core/geometry/indenter.hpp"

namespace sb {

std::vector<Vec2> marker_grid_px(const MarkerGrid& grid, const Camera& camera) {
  // Marker (r, c) sits (c - (cols-1)/2, r - (rows-1)/2) pitches from the principal point.
  std::vector<Vec2> uv;
  uv.reserve(static_cast<std::size_t>(grid.rows) * grid.cols);
  const double c0 = 0.5 * (grid.cols - 1), r0 = 0.5 * (grid.rows - 1);
  for (int r = 0; r < grid.rows; ++r)
    for (int c = 0; c < grid.cols; ++c)
      uv.push_back(camera.principal_px + grid.pitch_px * Vec2(c - c0, r - r0));
  return uv;
}

MarkerGrid parse_marker_grid(const std::string& text, const std::string& where) {
  static const std::regex kPattern(R"(\s*([0-9]{1,4})\s*[xX]\s*([0-9]{1,4})\s*)");
  std::smatch m;
  if (!std::regex_match(text, m, kPattern))
    throw InputError(where, "marker grid '" + text + "' is not of the form ROWSxCOLS (e.g. 7x9)");
  MarkerGrid grid;
  grid.rows = std::stoi(m[1].str());
  grid.cols = std::stoi(m[2].str());
  if (grid.rows < 1 || grid.cols < 1)
    throw InputError(where, "marker grid '" + text + "' needs at least one row and one column");
  return grid;
}

std::optional<VerticalSpan> vertical_span(const TriMesh& mesh, const Vec2& xy) {
  constexpr double kInsideSlack = 1e-12;  // barycentric slack so points on shared edges still hit
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const auto& f : mesh.faces) {
    const Vec3& a = mesh.vertices[static_cast<std::size_t>(f[0])];
    const Vec3& b = mesh.vertices[static_cast<std::size_t>(f[1])];
    const Vec3& c = mesh.vertices[static_cast<std::size_t>(f[2])];
    const Vec2 ab = (b - a).head<2>(), ac = (c - a).head<2>(), ap = xy - a.head<2>();
    const double det = ab.x() * ac.y() - ab.y() * ac.x();
    if (std::abs(det) < 1e-30) continue;  // a vertical triangle: the line grazes it at most
    const double s = (ap.x() * ac.y() - ap.y() * ac.x()) / det;
    const double t = (ab.x() * ap.y() - ab.y() * ap.x()) / det;
    if (s < -kInsideSlack || t < -kInsideSlack || s + t > 1 + kInsideSlack) continue;
    const double z = a.z() + s * (b.z() - a.z()) + t * (c.z() - a.z());
    lo = std::min(lo, z);
    hi = std::max(hi, z);
  }
  if (!(hi >= lo)) return std::nullopt;
  return VerticalSpan{lo, hi};
}

namespace {

TriMesh flat_pad_mesh(const GelSpec& gel) {
  TriMesh box = make_box_mesh(Vec3(gel.size_m.x(), gel.size_m.y(), gel.thickness_m));
  Pose X_E_box = Pose::Identity();
  X_E_box.translation() = Vec3(0, 0, -gel.thickness_m / 2);  // top face at z = 0
  return box.transformed(X_E_box);
}

std::vector<Vec3> markers_on_mesh(const TriMesh& mesh, const Camera& camera, const std::vector<Vec2>& uv) {
  std::vector<Vec3> p_EM;
  p_EM.reserve(uv.size());
  for (const Vec2& m : uv) {
    const Vec2 xy = camera.E_from_px(m);
    const auto span = vertical_span(mesh, xy);
    if (!span) {
      std::ostringstream s;
      s << "marker at (" << m.x() << ", " << m.y() << ") px lies outside the gel mesh footprint";
      throw InputError("gel mesh", s.str());
    }
    p_EM.emplace_back(xy.x(), xy.y(), span->z_high);
  }
  return p_EM;
}

}  // namespace

Sensor make_sensor(const Camera& camera, const GelSpec& gel, const std::vector<Vec2>& markers_rest_px,
                   const TriMesh* gel_mesh_E) {
  Sensor s;
  s.camera = camera;
  s.gel = gel;
  s.markers_rest_px = markers_rest_px;
  if (gel_mesh_E == nullptr) {
    if (gel.surface != "flat")
      throw std::invalid_argument("make_sensor: gel surface '" + gel.surface + "' needs its mesh in E");
    s.gel_sdf = make_pad_sdf(gel.size_m, gel.thickness_m);
    s.gel_mesh = flat_pad_mesh(gel);
    for (const Vec2& m : markers_rest_px) {
      const Vec2 xy = camera.E_from_px(m);
      s.p_EM.emplace_back(xy.x(), xy.y(), 0.0);
    }
    return s;
  }
  s.gel_mesh = *gel_mesh_E;
  const Eigen::AlignedBox3d box = s.gel_mesh.bounds();
  s.gel.size_m = box.sizes().head<2>();
  s.gel.thickness_m = -box.min().z();
  s.gel_sdf = make_mesh_sdf(s.gel_mesh);
  s.p_EM = markers_on_mesh(s.gel_mesh, camera, markers_rest_px);
  return s;
}

Sensor make_default_sensor() {
  const Camera camera;
  return make_sensor(camera, GelSpec{}, marker_grid_px(MarkerGrid{}, camera));
}

namespace {

// The xz extent of the vertices lying within `tol` of the extreme y on one side: small for the domed face
// (only its apex reaches the extreme), the whole face for the flat one.
double extreme_face_spread(const TriMesh& mesh, double y_extreme, double tol) {
  Eigen::AlignedBox2d spread;
  for (const Vec3& v : mesh.vertices)
    if (std::abs(v.y() - y_extreme) <= tol) spread.extend(Vec2(v.x(), v.z()));
  return spread.isEmpty() ? 0.0 : spread.diagonal().norm();
}

}  // namespace

TriMesh gelsight_mini_gel_in_E(const std::string& obj_path) {
  MeshLoadOptions load;
  load.scale = 1e-3;  // the CAD mesh is in millimetres
  const TriMesh cad = load_mesh(obj_path, load);
  const Eigen::AlignedBox3d box = cad.bounds();
  constexpr double kFaceTolerance = 1e-5;  // metres: vertices this close to an extreme lie on that face
  const bool dome_at_max_y = extreme_face_spread(cad, box.max().y(), kFaceTolerance) <
                             extreme_face_spread(cad, box.min().y(), kFaceTolerance);
  // Rotation taking the CAD axes into E: CAD x stays x, the thin axis y (dome side) becomes +z, and the
  // in-plane CAD z becomes +-y so that the rotation is proper (det = +1, faces keep their outward winding).
  Mat3 R_E_cad;
  if (dome_at_max_y)
    R_E_cad << 1, 0, 0, 0, 0, -1, 0, 1, 0;
  else
    R_E_cad << 1, 0, 0, 0, 0, 1, 0, -1, 0;
  const Vec3 apex_cad(box.center().x(), dome_at_max_y ? box.max().y() : box.min().y(), box.center().z());
  Pose X_E_cad = Pose::Identity();
  X_E_cad.linear() = R_E_cad;
  X_E_cad.translation() = -R_E_cad * apex_cad;  // the apex (centre of the domed face) goes to the origin
  return cad.transformed(X_E_cad);
}

}  // namespace sb
