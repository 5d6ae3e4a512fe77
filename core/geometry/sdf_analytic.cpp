// Exact signed distance fields of simple shapes. Gradients are the analytic outward normals; at the
// few points where the gradient is undefined (sphere centre, torus axis) a fixed direction is returned.
#include <algorithm>
#include <cmath>
#include <sstream>

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
  static Vec3 sign_or_one(const Vec3& s) { return s.unaryExpr([](double v) { return v == 0 ? 1.0 : v; }); }
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
SdfPtr make_box_sdf(const Vec3& size) { return std::make_shared<BoxSdf>(Vec3::Zero(), size / 2); }
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
