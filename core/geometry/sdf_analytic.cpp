// Exact signed distance fields of simple shapes. Gradients are the analytic outward normals; at the
// few points where the gradient is undefined (sphere centre, torus axis) a fixed direction is returned.
#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "core/base/vector_clones.hpp"
#include "core/geometry/sdf.hpp"

namespace sb {

void Sdf::values(std::span<const Vec3> p, std::span<double> phi) const {
  for (std::size_t i = 0; i < p.size(); ++i) phi[i] = value(p[i]);
}

void Sdf::values_and_gradients(std::span<const Vec3> p, std::span<double> phi, std::span<Vec3> gradient) const {
  for (std::size_t i = 0; i < p.size(); ++i) phi[i] = value_and_gradient(p[i], &gradient[i]);
}

namespace {

constexpr double kHuge = 1e3;  // metres: "everywhere" for the bounds of unbounded fields

class SphereSdf final : public Sdf {
 public:
  SphereSdf(double r, const Vec3& c) : r_(r), c_(c) {}
  double value(const Vec3& p) const override { return (p - c_).norm() - r_; }
  double value_and_gradient(const Vec3& p, Vec3* g) const override {
    const Vec3 d = p - c_;
    const double n = d.norm();
    *g = n > 0 ? Vec3(d / n) : Vec3::UnitZ();
    return n - r_;
  }
  // Batch forms without a virtual call per point (the shear models query 63 markers per slot).
  void values(std::span<const Vec3> p, std::span<double> phi) const override {
    for (std::size_t i = 0; i < p.size(); ++i) phi[i] = SphereSdf::value(p[i]);
  }
  void values_and_gradients(std::span<const Vec3> p, std::span<double> phi, std::span<Vec3> g) const override {
    for (std::size_t i = 0; i < p.size(); ++i) phi[i] = SphereSdf::value_and_gradient(p[i], &g[i]);
  }
  Eigen::AlignedBox3d bounds() const override { return {c_ - Vec3::Constant(2 * r_), c_ + Vec3::Constant(2 * r_)}; }
  std::string describe() const override {
    std::ostringstream s;
    s << "analytic sphere r=" << r_ << " m";
    return s.str();
  }

 private:
  double r_;
  Vec3 c_;
};

// The gel of a dome sensor (sensor.cpp's spherical_cap_mesh, exactly): the part of the ball of radius R about
// (0, 0, -R) above its rim z_rim = -R (1 - cos theta_max), F = R sin theta_max the footprint radius, on a
// cylinder r <= F from z_rim down to -T. Worked in the (r, z) half-plane of a solid of revolution: the
// distance is the one to the nearest of the profile's arc, wall and bottom; inside is the union of the two.
struct CapShape {
  double R, F, T, z_rim, sin_rim, cos_rim;
};

// The cap's signed distance at (x, y, z): squared distances to the arc's circle or its rim end, the wall and the
// bottom, one square root each. Selects, no branches: cap_distances vectorises it over points.
inline double cap_distance(const CapShape& c, double x, double y, double z) {
  const double r = std::sqrt(x * x + y * y), zc = z + c.R;
  const double arc = std::sqrt(r * r + zc * zc) - c.R;
  const double to_rim = (r - c.F) * (r - c.F) + (z - c.z_rim) * (z - c.z_rim);
  double d2 = r * c.cos_rim - zc * c.sin_rim > 0 ? to_rim : arc * arc;
  const double zw = z - std::clamp(z, -c.T, c.z_rim);
  d2 = std::min(d2, (r - c.F) * (r - c.F) + zw * zw);
  const double rb = r - std::min(r, c.F);
  d2 = std::min(d2, rb * rb + (z + c.T) * (z + c.T));
  const bool inside = (z >= -c.T) & (((z <= c.z_rim) & (r <= c.F)) | ((z > c.z_rim) & (r * r + zc * zc <= c.R * c.R)));
  return inside ? -std::sqrt(d2) : std::sqrt(d2);
}

SB_VECTOR_CLONES
void cap_distances(const CapShape& c, const Vec3* p, int n, double* phi) {
  SB_IVDEP
  for (int i = 0; i < n; ++i) phi[i] = cap_distance(c, p[i].x(), p[i].y(), p[i].z());
}

class SphericalCapSdf final : public Sdf {
 public:
  SphericalCapSdf(double R, double F, double T)
      : R_(R),
        F_(F),
        T_(T),
        z_rim_(-(R - std::sqrt(std::max(R * R - F * F, 0.0)))),
        sin_rim_(F / R),
        cos_rim_((z_rim_ + R) / R),
        shape_{R_, F_, T_, z_rim_, sin_rim_, cos_rim_} {}
  // The distance alone (HydroShear asks it of every point near the gel at every step): cap_distance.
  double value(const Vec3& p) const override { return cap_distance(shape_, p.x(), p.y(), p.z()); }
  double value_and_gradient(const Vec3& p, Vec3* g) const override {
    const double r = std::sqrt(p.x() * p.x() + p.y() * p.y()), z = p.z();
    const Vec2 q(r, z);
    Vec2 nearest = nearest_on_arc(q);
    for (const Vec2& c :
         {nearest_on_segment(q, Vec2(F_, z_rim_), Vec2(F_, -T_)), nearest_on_segment(q, Vec2(F_, -T_), Vec2(0, -T_))})
      if ((q - c).squaredNorm() < (q - nearest).squaredNorm()) nearest = c;
    const bool inside = z >= -T_ &&
                        ((z <= z_rim_ && r <= F_) || (z > z_rim_ && r * r + (z + R_) * (z + R_) <= R_ * R_));
    const Vec2 d = q - nearest;
    const double dist = d.norm();
    const Vec2 radial = r > 0 ? Vec2(p.x() / r, p.y() / r) : Vec2(1, 0);
    const Vec2 n2 = dist > 0 ? Vec2(d / dist * (inside ? -1.0 : 1.0)) : Vec2(0, 1);
    *g = Vec3(n2.x() * radial.x(), n2.x() * radial.y(), n2.y());
    return inside ? -dist : dist;
  }
  void values(std::span<const Vec3> p, std::span<double> phi) const override {
    cap_distances(shape_, p.data(), static_cast<int>(p.size()), phi.data());
  }
  Eigen::AlignedBox3d bounds() const override {
    const double e = 2 * std::max(F_, T_);
    return {Vec3(-e, -e, -2 * T_), Vec3(e, e, T_)};
  }
  std::string describe() const override {
    std::ostringstream s;
    s << "analytic spherical cap R=" << R_ << " footprint " << F_ << " thickness " << T_ << " m";
    return s.str();
  }

 private:
  // Nearest point of the arc from the apex (0, 0) to the rim (F, z_rim), centre (0, -R). v = q - centre at
  // polar angle t (from +z, t >= 0 since r >= 0): v x u(t_rim) = |v| sin(t - t_rim) <= 0 iff t <= t_rim.
  Vec2 nearest_on_arc(const Vec2& q) const {
    const Vec2 v = q - Vec2(0, -R_);
    if (v.x() * cos_rim_ - v.y() * sin_rim_ > 0) return Vec2(F_, z_rim_);
    const double n = v.norm();
    if (n == 0 || (v.x() <= 0 && v.y() < 0)) return Vec2(0, 0);  // the centre, or straight below it
    return Vec2(0, -R_) + (R_ / n) * v;
  }
  static Vec2 nearest_on_segment(const Vec2& q, const Vec2& a, const Vec2& b) {
    const Vec2 ab = b - a;
    const double t = std::clamp((q - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
    return a + t * ab;
  }
  double R_, F_, T_, z_rim_, sin_rim_, cos_rim_;
  CapShape shape_;
};

class TorusSdf final : public Sdf {
 public:
  TorusSdf(double R, double r) : R_(R), r_(r) {}
  // Distance to the tube's centre circle (radius R in the z = 0 plane) minus the tube radius.
  double value(const Vec3& p) const override {
    const double q = std::hypot(p.x(), p.y()) - R_;
    return std::hypot(q, p.z()) - r_;
  }
  double value_and_gradient(const Vec3& p, Vec3* g) const override {
    const double rho = std::hypot(p.x(), p.y());
    const Vec3 radial = rho > 0 ? Vec3(p.x() / rho, p.y() / rho, 0) : Vec3::UnitX();
    const Vec3 centre = R_ * radial;  // nearest point of the centre circle
    const Vec3 d = p - centre;
    const double n = d.norm();
    *g = n > 0 ? Vec3(d / n) : Vec3::UnitZ();
    return n - r_;
  }
  Eigen::AlignedBox3d bounds() const override {
    const double e = R_ + 2 * r_;
    return {Vec3(-e, -e, -2 * r_), Vec3(e, e, 2 * r_)};
  }
  std::string describe() const override {
    std::ostringstream s;
    s << "analytic torus R=" << R_ << " r=" << r_ << " m";
    return s.str();
  }

 private:
  double R_, r_;
};

class BoxSdf final : public Sdf {
 public:
  BoxSdf(const Vec3& centre, const Vec3& half) : c_(centre), h_(half) {}
  double value(const Vec3& p) const override {
    Vec3 g;
    return value_and_gradient(p, &g);
  }
  double value_and_gradient(const Vec3& p, Vec3* g) const override {
    const Vec3 q = (p - c_).cwiseAbs() - h_;
    const Vec3 s = (p - c_).cwiseSign();
    const Vec3 outside = q.cwiseMax(0.0);
    const double out_norm = outside.norm();
    if (out_norm > 0) {
      // Outside: nearest point on the box; gradient points from it to p.
      *g = outside.cwiseProduct(sign_or_one(s)) / out_norm;
      return out_norm;
    }
    // Inside: the nearest face is the one with the largest (least negative) q.
    int axis = 0;
    q.maxCoeff(&axis);
    *g = Vec3::Zero();
    (*g)[axis] = s[axis] != 0 ? s[axis] : 1.0;
    return q[axis];
  }
  Eigen::AlignedBox3d bounds() const override { return {c_ - 2 * h_, c_ + 2 * h_}; }
  std::string describe() const override {
    std::ostringstream s;
    s << "analytic box " << 2 * h_.x() << " x " << 2 * h_.y() << " x " << 2 * h_.z() << " m";
    return s.str();
  }

 private:
  static Vec3 sign_or_one(const Vec3& s) {
    return s.unaryExpr([](double v) { return v == 0 ? 1.0 : v; });
  }
  Vec3 c_, h_;
};

class CappedCylinderSdf final : public Sdf {
 public:
  CappedCylinderSdf(double r, double L) : r_(r), h_(L / 2) {}
  double value(const Vec3& p) const override {
    Vec3 g;
    return value_and_gradient(p, &g);
  }
  // In the (rho, z) half-plane the cylinder is the rectangle [0, r] x [-h, h]: the 2-D box distance.
  double value_and_gradient(const Vec3& p, Vec3* g) const override {
    // sqrt rather than std::hypot (several times slower in glibc): no overflow risk at these scales,
    // and the result differs by at most an ulp.
    const double rho = std::sqrt(p.x() * p.x() + p.y() * p.y());
    const Vec3 radial = rho > 0 ? Vec3(p.x() / rho, p.y() / rho, 0) : Vec3::UnitX();
    const double sz = p.z() >= 0 ? 1.0 : -1.0;
    const double dr = rho - r_;
    const double dz = std::abs(p.z()) - h_;
    if (dr > 0 || dz > 0) {
      const double er = std::max(dr, 0.0), ez = std::max(dz, 0.0);
      const double n = std::sqrt(er * er + ez * ez);
      *g = (er * radial + ez * sz * Vec3::UnitZ()) / n;
      return n;
    }
    if (dr > dz) {
      *g = radial;
      return dr;
    }
    *g = sz * Vec3::UnitZ();
    return dz;
  }
  // Batch forms without a virtual call per point (the shear models query 63 markers per slot).
  // The value alone, as value_and_gradient computes it (same operations, no normal).
  void values(std::span<const Vec3> p, std::span<double> phi) const override {
    for (std::size_t i = 0; i < p.size(); ++i) {
      const double rho = std::sqrt(p[i].x() * p[i].x() + p[i].y() * p[i].y());
      const double dr = rho - r_, dz = std::abs(p[i].z()) - h_;
      const double er = std::max(dr, 0.0), ez = std::max(dz, 0.0);
      phi[i] = dr > 0 || dz > 0 ? std::sqrt(er * er + ez * ez) : std::max(dr, dz);
    }
  }
  void values_and_gradients(std::span<const Vec3> p, std::span<double> phi, std::span<Vec3> g) const override {
    for (std::size_t i = 0; i < p.size(); ++i) phi[i] = CappedCylinderSdf::value_and_gradient(p[i], &g[i]);
  }
  Eigen::AlignedBox3d bounds() const override {
    return {Vec3(-2 * r_, -2 * r_, -2 * h_), Vec3(2 * r_, 2 * r_, 2 * h_)};
  }
  std::string describe() const override {
    std::ostringstream s;
    s << "analytic capped cylinder r=" << r_ << " L=" << 2 * h_ << " m";
    return s.str();
  }

 private:
  double r_, h_;
};

class HalfspaceSdf final : public Sdf {
 public:
  double value(const Vec3& p) const override { return p.z(); }
  double value_and_gradient(const Vec3& p, Vec3* g) const override {
    *g = Vec3::UnitZ();
    return p.z();
  }
  Eigen::AlignedBox3d bounds() const override { return {Vec3::Constant(-kHuge), Vec3::Constant(kHuge)}; }
  std::string describe() const override { return "half-space z <= 0"; }
};

class TransformedSdf final : public Sdf {
 public:
  TransformedSdf(SdfPtr inner, const Pose& X_AB) : inner_(std::move(inner)), X_AB_(X_AB), X_BA_(X_AB.inverse()) {}
  double value(const Vec3& p_A) const override { return inner_->value(X_BA_ * p_A); }
  double value_and_gradient(const Vec3& p_A, Vec3* g_A) const override {
    Vec3 g_B;
    const double v = inner_->value_and_gradient(X_BA_ * p_A, &g_B);
    *g_A = X_AB_.linear() * g_B;
    return v;
  }
  Eigen::AlignedBox3d bounds() const override {
    const auto b = inner_->bounds();
    Eigen::AlignedBox3d out;
    for (int k = 0; k < 8; ++k) out.extend(X_AB_ * b.corner(static_cast<Eigen::AlignedBox3d::CornerType>(k)));
    return out;
  }
  std::string describe() const override { return inner_->describe() + " (transformed)"; }

 private:
  SdfPtr inner_;
  Pose X_AB_, X_BA_;
};

}  // namespace

SdfPtr make_sphere_sdf(double radius, const Vec3& centre) { return std::make_shared<SphereSdf>(radius, centre); }
SdfPtr make_torus_sdf(double R, double r) { return std::make_shared<TorusSdf>(R, r); }
SdfPtr make_spherical_cap_sdf(double radius, double footprint_radius, double thickness) {
  if (!(radius > 0 && footprint_radius > 0 && footprint_radius <= radius && thickness > 0))
    throw std::invalid_argument("make_spherical_cap_sdf: needs 0 < footprint radius <= radius and thickness > 0");
  if (thickness < radius - std::sqrt(radius * radius - footprint_radius * footprint_radius))
    throw std::invalid_argument("make_spherical_cap_sdf: the thickness ends above the cap's rim");
  return std::make_shared<SphericalCapSdf>(radius, footprint_radius, thickness);
}
SdfPtr make_box_sdf(const Vec3& size, const Vec3& centre) { return std::make_shared<BoxSdf>(centre, size / 2); }
SdfPtr make_pad_sdf(const Vec2& size, double thickness) {
  const Vec3 half(size.x() / 2, size.y() / 2, thickness / 2);
  return std::make_shared<BoxSdf>(Vec3(0, 0, -thickness / 2), half);
}
SdfPtr make_capped_cylinder_sdf(double radius, double length) {
  return std::make_shared<CappedCylinderSdf>(radius, length);
}
SdfPtr make_halfspace_sdf() { return std::make_shared<HalfspaceSdf>(); }
SdfPtr make_transformed_sdf(SdfPtr inner_B, const Pose& X_AB) {
  return std::make_shared<TransformedSdf>(std::move(inner_B), X_AB);
}

}  // namespace sb
