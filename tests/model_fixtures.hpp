#pragma once
// Test fixtures for the shear models: the default GelSight Mini pad with its 7 x 9 marker grid built
// directly (33 px pitch, 0.0634 mm/px, centred: first marker (27.5, 20.5) px, last (291.5, 218.5) px),
// a sphere with deterministic Fibonacci surface points, and a flat-bottomed box whose tracked points
// are a grid on its bottom face.
#include <cmath>
#include <memory>
#include <numbers>

#include "core/geometry/indenter.hpp"
#include "core/models/model.hpp"
#include "core/sensor/sensor.hpp"
#include "test_poses.hpp"

namespace sbtest {

using namespace sb;

inline constexpr double kPitchM = 33 * 0.0634e-3;  // 2.0922 mm

inline std::shared_ptr<const Sensor> test_sensor() {
  auto s = std::make_shared<Sensor>();
  s->camera = Camera{};
  s->gel = GelSpec{};
  for (int r = 0; r < 7; ++r)
    for (int c = 0; c < 9; ++c) {
      const Vec2 uv(s->camera.principal_px.x() + (c - 4) * 33.0, s->camera.principal_px.y() + (r - 3) * 33.0);
      s->markers_rest_px.push_back(uv);
      const Vec2 xy = s->camera.E_from_px(uv);
      s->p_EM.emplace_back(xy.x(), xy.y(), 0.0);
    }
  s->gel_sdf = make_pad_sdf(s->gel.size_m, s->gel.thickness_m);
  return s;
}

// Index of the marker at grid offset (dc, dr) from the centre marker (column 4, row 3).
inline int marker_at(int dc, int dr) { return (3 + dr) * 9 + (4 + dc); }

// Equal-area Fibonacci points on a sphere of radius r centred at the origin of I.
inline std::shared_ptr<const Indenter> sphere_indenter(double r, int n = 400) {
  auto ind = std::make_shared<Indenter>();
  ind->name = "sphere";
  ind->sdf = make_sphere_sdf(r);
  const double golden = std::numbers::pi * (3 - std::sqrt(5.0));
  for (int i = 0; i < n; ++i) {
    const double z = 1 - (2.0 * i + 1) / n;
    const double rho = std::sqrt(1 - z * z);
    const Vec3 dir(rho * std::cos(golden * i), rho * std::sin(golden * i), z);
    ind->samples.p_IS.push_back(r * dir);
    ind->samples.n_IS.push_back(dir);
    ind->samples.area_m2.push_back(4 * std::numbers::pi * r * r / n);
  }
  return ind;
}

// A box of full size (a, a, a); tracked points: an n x n grid with spacing `spacing` on the bottom face
// z = -a/2 (normal -z), centred.
inline std::shared_ptr<const Indenter> box_indenter(double a, int n = 5, double spacing = 1e-3) {
  auto ind = std::make_shared<Indenter>();
  ind->name = "box";
  ind->sdf = make_box_sdf(Vec3(a, a, a));
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      ind->samples.p_IS.emplace_back((i - (n - 1) / 2.0) * spacing, (j - (n - 1) / 2.0) * spacing, -a / 2);
      ind->samples.n_IS.emplace_back(0, 0, -1);
      ind->samples.area_m2.push_back(spacing * spacing);
    }
  return ind;
}

// X_EI placing the box's bottom face at height z_bottom (negative: pressed in) centred at (x, y).
inline Pose box_pose(double a, double x, double y, double z_bottom, double yaw = 0) {
  Pose X = Pose::Identity();
  X.linear() = Rz(yaw);
  X.translation() = Vec3(x, y, z_bottom + a / 2);
  return X;
}

inline std::vector<Vec2> run(ShearModel& m, const Pose& X, double dt = 0.01) {
  FieldOutput out;
  m.step(X, dt, &out);
  return out.disp_px;
}

inline double max_norm(const std::vector<Vec2>& d) {
  double m = 0;
  for (const Vec2& v : d) m = std::max(m, v.norm());
  return m;
}

}  // namespace sbtest
