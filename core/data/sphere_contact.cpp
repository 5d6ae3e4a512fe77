// Sphere contact estimated from a marker displacement field (sphere_contact.hpp).
#include "core/data/sphere_contact.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/base/median.hpp"
#include "core/base/numbers.hpp"

namespace sb {

double sphere_depth_from_contact_radius(double R, double a) {
  if (!(a >= 0) || a > R) return kNaN;
  return R - std::sqrt(R * R - a * a);
}

SphereContactEstimate estimate_sphere_contact_with_radius(const std::vector<Vec2>& rest, const std::vector<Vec2>& disp,
                                                          const Vec2& centre_px, double a_px, double a_sigma_px) {
  SphereContactEstimate e;
  std::vector<double> dx, dy;
  for (const auto& d : disp) dx.push_back(d.x()), dy.push_back(d.y());
  e.drift_px = Vec2(median(dx), median(dy));
  e.centre_px = centre_px;
  e.a_px = a_px;
  e.a_sigma_px = a_sigma_px;
  std::vector<Vec2> inside;
  Vec2 mean = Vec2::Zero();
  for (std::size_t i = 0; i < rest.size(); ++i)
    if ((rest[i] - centre_px).norm() <= a_px) inside.push_back(disp[i] - e.drift_px), mean += inside.back();
  e.markers_inside = static_cast<int>(inside.size());
  if (!inside.empty()) {
    mean /= double(inside.size());
    double var = 0;
    for (const auto& v : inside) var += (v - mean).squaredNorm();
    // Standard error of the mean, with the 1 px integer quantisation of the CSV added in quadrature.
    e.travel_sigma_px = std::sqrt(var / double(inside.size()) / double(inside.size()) + 1.0 / 12.0);
  }
  e.travel_px = mean;
  return e;
}

SphereContactEstimate estimate_sphere_contact(const std::vector<Vec2>& rest, const std::vector<Vec2>& disp,
                                              double pitch) {
  SphereContactEstimate e;
  const std::size_t n = rest.size();
  std::vector<double> dx, dy;
  for (const auto& d : disp) dx.push_back(d.x()), dy.push_back(d.y());
  e.drift_px = Vec2(median(dx), median(dy));
  std::vector<Vec2> d(n);
  double peak = 0;
  for (std::size_t i = 0; i < n; ++i) d[i] = disp[i] - e.drift_px, peak = std::max(peak, d[i].norm());
  // Centre: |d|-weighted centroid of the strongly displaced markers.
  double sw = 0;
  for (std::size_t i = 0; i < n; ++i)
    if (d[i].norm() >= 0.5 * peak) e.centre_px += d[i].norm() * rest[i], sw += d[i].norm();
  if (sw > 0) e.centre_px /= sw;
  // Contact radius: the ring (width half a pitch) with the largest mean radial displacement.
  const double ring = 0.5 * pitch;
  std::vector<double> sum, count;
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2 r = rest[i] - e.centre_px;
    const double rn = r.norm();
    if (rn < 1e-9) continue;
    const std::size_t k = static_cast<std::size_t>(rn / ring);
    if (k >= sum.size()) sum.resize(k + 1, 0.0), count.resize(k + 1, 0.0);
    sum[k] += d[i].dot(r / rn), count[k] += 1;
  }
  double best = -std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < sum.size(); ++k)
    if (count[k] > 0 && sum[k] / count[k] > best) best = sum[k] / count[k], e.a_px = (k + 0.5) * ring;
  e.a_sigma_px = 0.5 * pitch;
  return estimate_sphere_contact_with_radius(rest, disp, e.centre_px, e.a_px, e.a_sigma_px);
}

}  // namespace sb
