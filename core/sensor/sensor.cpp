// The GelSight Mini elastomer: marker layout, gel geometry and SDF, and the real domed gel placed into E.
#include "core/sensor/sensor.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <regex>
#include <sstream>
#include <stdexcept>

#include "core/geometry/indenter.hpp"
#include "core/geometry/sdf_cache.hpp"

namespace sb {

std::vector<Vec2> marker_grid_px(const MarkerGrid& grid, const Camera& camera) {
  // Marker (r, c) sits (c - (cols-1)/2, r - (rows-1)/2) pitches from the principal point.
  std::vector<Vec2> uv;
  uv.reserve(static_cast<std::size_t>(grid.rows) * grid.cols);
  const double c0 = 0.5 * (grid.cols - 1), r0 = 0.5 * (grid.rows - 1);
  for (int r = 0; r < grid.rows; ++r)
    for (int c = 0; c < grid.cols; ++c) uv.push_back(camera.principal_px + grid.pitch_px * Vec2(c - c0, r - r0));
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

std::string marker_text(const Vec2& m) {
  std::ostringstream s;
  s << "marker at (" << m.x() << ", " << m.y() << ") px";
  return s.str();
}

// Orthographic markers under a mesh gel: at the surface height under them, `depth` lower (along -z, which is
// the normal where the gel is flat, as the GelSight Mini's nearly is).
std::vector<Vec3> markers_on_mesh(const TriMesh& mesh, const Camera& camera, const std::vector<Vec2>& uv,
                                  double depth) {
  std::vector<Vec3> p_EM;
  p_EM.reserve(uv.size());
  for (const Vec2& m : uv) {
    const Vec2 xy = camera.E_from_px(m);
    const auto span = vertical_span(mesh, xy);
    if (!span) throw InputError("gel mesh", marker_text(m) + " lies outside the gel mesh footprint");
    p_EM.emplace_back(xy.x(), xy.y(), span->z_high - depth);
  }
  return p_EM;
}

// Markers on the plane z = -depth: under their pixel (orthographic) or where their ray meets it (pinhole).
std::vector<Vec3> markers_on_plane(const Camera& camera, const std::vector<Vec2>& uv, double depth) {
  std::vector<Vec3> p_EM;
  p_EM.reserve(uv.size());
  for (const Vec2& m : uv) {
    if (!camera.pinhole()) {  // as before depths existed: E_from_px, bit for bit (z = +0.0 at depth 0, not -0.0)
      const Vec2 xy = camera.E_from_px(m);
      p_EM.emplace_back(xy.x(), xy.y(), depth > 0.0 ? -depth : 0.0);
      continue;
    }
    const auto ray = camera.back_project(m);
    if (!ray) throw InputError("camera", marker_text(m) + " lies beyond the invertible range of the distortion");
    const double t = (-depth - ray->origin_E.z()) / ray->direction_E.z();
    p_EM.push_back(ray->origin_E + t * ray->direction_E);
  }
  return p_EM;
}

// Markers on the pin sphere of a spherical cap (radius R - depth about (0, 0, -R)), within the cap's polar
// angle: under their pixel (orthographic) or the upper crossing of their ray (pinhole).
std::vector<Vec3> markers_on_cap(const GelSpec& gel, const Camera& camera, const std::vector<Vec2>& uv) {
  const Vec3 c_E(0.0, 0.0, -gel.radius_m);
  const double rp = gel.radius_m - gel.markers_depth_m;
  const double cos_max = std::sqrt(std::max(0.0, 1.0 - std::pow(gel.footprint_radius_m / gel.radius_m, 2)));
  constexpr double kRimSlack = 1e-9;  // cosine slack so markers placed exactly on the rim stay
  std::vector<Vec3> p_EM;
  p_EM.reserve(uv.size());
  for (const Vec2& m : uv) {
    const auto ray = camera.back_project(m);
    if (!ray) throw InputError("camera", marker_text(m) + " lies beyond the invertible range of the distortion");
    // |o + t d - c|^2 = rp^2 with |d| = 1: t^2 + 2 t b + q = 0, b = d.(o - c), q = |o - c|^2 - rp^2.
    const Vec3 oc = ray->origin_E - c_E;
    const double b = ray->direction_E.dot(oc), q = oc.squaredNorm() - rp * rp;
    const double disc = b * b - q;
    if (disc < 0.0) throw InputError("gel spherical cap", marker_text(m) + " does not see the pin surface");
    // The upper crossing: the larger root for the pinhole's upward ray, the smaller for the orthographic
    // downward one.
    const double t = camera.pinhole() ? -b + std::sqrt(disc) : -b - std::sqrt(disc);
    const Vec3 p = ray->origin_E + t * ray->direction_E;
    if ((p - c_E).z() / rp < cos_max - kRimSlack)
      throw InputError("gel spherical cap", marker_text(m) + " lies outside the cap's footprint");
    p_EM.push_back(p);
  }
  return p_EM;
}

void check_cap(const GelSpec& gel) {
  const double R = gel.radius_m, rho = gel.footprint_radius_m;
  if (!(R > 0.0) || !(rho > 0.0) || rho > R)
    throw std::invalid_argument("spherical cap: needs 0 < footprint_radius_m <= radius_m");
  const double cap_height = R - std::sqrt(R * R - rho * rho);
  if (!(gel.thickness_m > cap_height))
    throw std::invalid_argument("spherical cap: thickness_m must exceed the cap height " + std::to_string(cap_height) +
                                " m");
  if (!(gel.markers_depth_m >= 0.0) || gel.markers_depth_m >= R)
    throw std::invalid_argument("spherical cap: needs 0 <= markers_depth_m < radius_m");
}

}  // namespace

bool gel_surface_is_mesh(const std::string& surface) { return surface != "flat" && surface != "spherical_cap"; }

TriMesh spherical_cap_mesh(const GelSpec& gel, int segments, int rings) {
  check_cap(gel);
  if (segments < 3 || rings < 1) throw std::invalid_argument("spherical_cap_mesh: needs segments >= 3, rings >= 1");
  const double R = gel.radius_m, theta_max = std::asin(gel.footprint_radius_m / R);
  TriMesh mesh;
  auto& v = mesh.vertices;
  v.emplace_back(0.0, 0.0, 0.0);  // apex
  const double two_pi = 2.0 * std::acos(-1.0);
  auto ring_point = [&](double radius, double z, int j) {
    const double phi = two_pi * j / segments;
    return Vec3(radius * std::cos(phi), radius * std::sin(phi), z);
  };
  for (int i = 1; i <= rings; ++i) {  // ring i at polar angle theta_max * i / rings on the sphere
    const double theta = theta_max * i / rings;
    for (int j = 0; j < segments; ++j) v.push_back(ring_point(R * std::sin(theta), -R * (1.0 - std::cos(theta)), j));
  }
  const int bottom_ring = static_cast<int>(v.size());
  for (int j = 0; j < segments; ++j) v.push_back(ring_point(gel.footprint_radius_m, -gel.thickness_m, j));
  const int bottom_centre = static_cast<int>(v.size());
  v.emplace_back(0.0, 0.0, -gel.thickness_m);
  auto ring = [&](int i, int j) { return 1 + (i - 1) * segments + (j % segments); };  // i in 1..rings
  auto& f = mesh.faces;
  for (int j = 0; j < segments; ++j) {  // counter-clockwise seen from outside
    f.emplace_back(0, ring(1, j), ring(1, j + 1));
    for (int i = 1; i < rings; ++i) {
      f.emplace_back(ring(i, j), ring(i + 1, j), ring(i + 1, j + 1));
      f.emplace_back(ring(i, j), ring(i + 1, j + 1), ring(i, j + 1));
    }
    const int t0 = ring(rings, j), t1 = ring(rings, j + 1);
    const int b0 = bottom_ring + j, b1 = bottom_ring + (j + 1) % segments;
    f.emplace_back(t0, b0, b1);  // the wall
    f.emplace_back(t0, b1, t1);
    f.emplace_back(bottom_centre, b1, b0);  // the bottom, facing -z
  }
  return mesh;
}

Sensor make_sensor(const Camera& camera, const GelSpec& gel, const std::vector<Vec2>& markers_rest_px,
                   const TriMesh* gel_mesh_E) {
  Sensor s;
  s.camera = camera;
  s.gel = gel;
  s.markers_rest_px = markers_rest_px;
  if (!(gel.markers_depth_m >= 0.0)) throw std::invalid_argument("make_sensor: markers_depth_m must be >= 0");
  std::optional<double> pin_surface_centre_z;  // nullopt: the pins lie on a plane (or under a mesh)
  if (gel.surface == "flat" && gel_mesh_E == nullptr) {
    s.gel_sdf = make_pad_sdf(gel.size_m, gel.thickness_m);
    s.gel_mesh = flat_pad_mesh(gel);
    s.p_EM = markers_on_plane(camera, markers_rest_px, gel.markers_depth_m);
  } else if (gel.surface == "spherical_cap" && gel_mesh_E == nullptr) {
    s.gel_mesh = spherical_cap_mesh(gel);
    s.gel.size_m = s.gel_mesh.bounds().sizes().head<2>();
    // The exact field, not the mesh's sampled one: the same solid without facets, and a few operations per
    // point against a tree lookup (the TacTip's fits spent a third of their time there).
    s.gel_sdf = make_spherical_cap_sdf(gel.radius_m, gel.footprint_radius_m, gel.thickness_m);
    s.p_EM = markers_on_cap(gel, camera, markers_rest_px);
    pin_surface_centre_z = -gel.radius_m;
  } else {
    if (gel_mesh_E == nullptr)
      throw std::invalid_argument("make_sensor: gel surface '" + gel.surface + "' needs its mesh in E");
    if (camera.pinhole())
      throw std::invalid_argument("make_sensor: a pinhole camera needs a flat or spherical_cap gel, not a mesh file");
    s.gel_mesh = *gel_mesh_E;
    s.p_EM = markers_on_mesh(s.gel_mesh, camera, markers_rest_px, gel.markers_depth_m);
  }
  if (!s.gel_sdf) {  // a mesh gel (given or generated)
    const Eigen::AlignedBox3d box = s.gel_mesh.bounds();
    s.gel.size_m = box.sizes().head<2>();
    s.gel.thickness_m = -box.min().z();
    s.gel_sdf = cached_mesh_sdf(s.gel_mesh, {});  // every dataset load builds its sensor: once per gel
  }
  if (camera.pinhole() || gel.markers_depth_m > 0.0)
    s.output_stage = SensorOutputStage(camera, s.p_EM, gel.markers_depth_m, pin_surface_centre_z);
  // The models see each marker where its pin meets the contact surface (along the normal): they compute the
  // surface field there, and the output stage (built from the pins above) carries it down to the pin and into
  // the image. So p_EM is the surface point over each pin.
  if (gel.markers_depth_m > 0.0) {
    for (Vec3& p : s.p_EM) {
      if (pin_surface_centre_z) {
        const Vec3 c_E(0.0, 0.0, *pin_surface_centre_z);
        p = c_E + (p - c_E) * (gel.radius_m / (gel.radius_m - gel.markers_depth_m));
      } else {
        p.z() += gel.markers_depth_m;
      }
    }
  }
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
