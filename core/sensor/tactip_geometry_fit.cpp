// The TacTip's camera and pin geometry from one rest image (tactip_geometry_fit.hpp).
#include "core/sensor/tactip_geometry_fit.hpp"

#include <ceres/ceres.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>

#include <Eigen/Eigenvalues>

#include "core/base/error.hpp"

namespace sb {
namespace {

constexpr int kMinPins = 19;                   // the apex pin and two full rings (1 + 6 + 12)
constexpr int kMinRings = 3;                   // rings 1..2 give the slope; a third is the least to see curvature
constexpr double kApexNeighbourSpread = 0.25;  // ring 1's six distances within 25 % of their median
constexpr double kSlotTolerance = 1.0 / 3.0;   // of the slot spacing 2 pi / (6 i)
// Below this reciprocal condition number of the column-scaled J^T J the free set is not identifiable (a
// direction the pins do not see): no sigma rather than a meaningless one.
constexpr double kMinCovarianceRcond = 1e-12;

double wrap_pi(double a) { return std::remainder(a, 2.0 * M_PI); }

// Pin (i, k) on the pin sphere and through the pinhole model of camera.hpp, templated for Ceres.
// x = {cu, cv, phi0, theta, f, D, k1}.
template <typename T>
void project_site(const T* const* x, double R, double rp, int ring, int slot, T* uv) {
  const T& cu = x[0][0];
  const T& cv = x[1][0];
  const T& phi0 = x[2][0];
  const T& theta = x[3][0];
  const T& f = x[4][0];
  const T& D = x[5][0];
  const T& k1 = x[6][0];
  const T t = double(ring) * theta;
  const T phi = ring == 0 ? phi0 : phi0 + 2.0 * M_PI * double(slot) / double(6 * ring);
  const T s = rp * sin(t);
  const T w = D - R + rp * cos(t);  // z + D with z = -R + rp cos t
  const T xn = s * cos(phi) / w, yn = s * sin(phi) / w;
  const T g = 1.0 + k1 * (xn * xn + yn * yn);
  uv[0] = cu + f * g * xn;
  uv[1] = cv + f * g * yn;
}

struct PinResidual {
  PinResidual(const Vec2& uv, double R, double rp, TactipPinSite site) : uv_(uv), R_(R), rp_(rp), site_(site) {}
  template <typename T>
  bool operator()(const T* const* x, T* r) const {
    T uv[2];
    project_site(x, R_, rp_, site_.ring, site_.slot, uv);
    r[0] = uv[0] - uv_.x();
    r[1] = uv[1] - uv_.y();
    return true;
  }
  Vec2 uv_;
  double R_, rp_;
  TactipPinSite site_;
};

constexpr int kParams = 7;
enum Param { kCu, kCv, kPhi0, kTheta, kFocal, kDistance, kK1 };

}  // namespace

TactipRings assign_tactip_rings(const std::vector<Vec2>& pins_px, const std::string& where) {
  const int n = int(pins_px.size());
  if (n < kMinPins)
    throw InputError(where, std::to_string(n) + " pins: the TacTip ring fit needs at least " +
                                std::to_string(kMinPins) + " (the apex pin and two full rings)");
  TactipRings out;
  out.sites.assign(n, TactipPinSite{});
  Vec2 centroid = Vec2::Zero();
  for (const Vec2& p : pins_px) centroid += p;
  centroid /= double(n);
  const int apex = int(std::min_element(pins_px.begin(), pins_px.end(),
                                        [&](const Vec2& a, const Vec2& b) {
                                          return (a - centroid).squaredNorm() < (b - centroid).squaredNorm();
                                        }) -
                       pins_px.begin());
  out.centre_px = pins_px[apex];
  std::vector<double> radius(n);
  for (int j = 0; j < n; ++j) radius[j] = (pins_px[j] - out.centre_px).norm();
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) { return radius[a] < radius[b]; });
  // Ring 1: the apex pin's six nearest neighbours at one distance.
  std::vector<double> first(6);
  for (int k = 0; k < 6; ++k) first[k] = radius[order[k + 1]];
  const double pitch = first[3];
  for (double r : first)
    if (std::abs(r - pitch) > kApexNeighbourSpread * pitch)
      throw InputError(where, "no apex pin with six neighbours at one distance (the pin nearest the centroid, at (" +
                                  std::to_string(out.centre_px.x()) + ", " + std::to_string(out.centre_px.y()) +
                                  ") px, has neighbours at " + std::to_string(first.front()) + " .. " +
                                  std::to_string(first.back()) + " px): not the TacTip ring pattern");
  out.sites[apex] = {0, 0};
  out.ring_radius_px = {0.0};
  std::vector<char> taken(n, 0);
  taken[apex] = 1;
  // phi0 from ring 1's six azimuths: the mean of 6 phi on the circle, over 6.
  {
    double c = 0, s = 0;
    for (int k = 1; k <= 6; ++k) {
      const Vec2 d = pins_px[order[k]] - out.centre_px;
      const double a = 6.0 * std::atan2(d.y(), d.x());
      c += std::cos(a);
      s += std::sin(a);
    }
    out.azimuth_rad = std::atan2(s, c) / 6.0;
  }
  for (int ring = 1;; ++ring) {
    const std::size_t m = out.ring_radius_px.size();
    const double spacing = ring == 1 ? pitch : out.ring_radius_px[m - 1] - out.ring_radius_px[m - 2];
    const double predicted = ring == 1 ? pitch : out.ring_radius_px[m - 1] + spacing;
    std::vector<int> members;
    for (int j : order)
      if (!taken[j] && std::abs(radius[j] - predicted) < 0.5 * spacing) members.push_back(j);
    if (members.empty()) break;
    const int slots = 6 * ring;
    if (int(members.size()) > slots)
      throw InputError(where, "ring " + std::to_string(ring) + " (image radius about " + std::to_string(predicted) +
                                  " px) holds " + std::to_string(members.size()) + " pins, more than its " +
                                  std::to_string(slots) + ": not the TacTip ring pattern");
    double sum = 0;
    std::vector<int> owner(slots, -1);
    std::vector<char> shared(slots, 0);
    for (int j : members) {
      taken[j] = 1;
      sum += radius[j];
      const Vec2 d = pins_px[j] - out.centre_px;
      const double step = 2.0 * M_PI / slots;
      const double u = wrap_pi(std::atan2(d.y(), d.x()) - out.azimuth_rad) / step;
      const double k = std::round(u);
      if (std::abs(u - k) > kSlotTolerance) continue;
      const int slot = (int(k) % slots + slots) % slots;
      if (owner[slot] >= 0) shared[slot] = 1;
      owner[slot] = j;
      out.sites[j] = {ring, slot};
    }
    for (int k = 0; k < slots; ++k)
      if (shared[k])
        for (int j : members)
          if (out.sites[j].ring == ring && out.sites[j].slot == k) out.sites[j] = TactipPinSite{};
    out.ring_radius_px.push_back(sum / double(members.size()));
  }
  if (int(out.ring_radius_px.size()) - 1 < kMinRings)
    throw InputError(where, "only " + std::to_string(out.ring_radius_px.size() - 1) +
                                " pin rings about the apex pin: the TacTip ring fit needs " +
                                std::to_string(kMinRings));
  for (const auto& s : out.sites) out.assigned += s.ring >= 0;
  return out;
}

Vec2 tactip_pin_px(const Camera& camera, double dome_radius_m, double pin_depth_m, double ring_pitch_rad,
                   double azimuth_rad, const TactipPinSite& site) {
  const double rp = dome_radius_m - pin_depth_m;
  const double t = site.ring * ring_pitch_rad;
  const double phi = site.ring == 0 ? azimuth_rad : azimuth_rad + 2.0 * M_PI * site.slot / (6.0 * site.ring);
  return camera.project(
      Vec3(rp * std::sin(t) * std::cos(phi), rp * std::sin(t) * std::sin(phi), -dome_radius_m + rp * std::cos(t)));
}

namespace {
// Dense QR on seven parameters, to tight tolerances (the fit is small and its covariance is read); one thread
// so the result does not depend on the machine.
ceres::Solver::Options pin_fit_solver_options() {
  ceres::Solver::Options so;
  so.linear_solver_type = ceres::DENSE_QR;
  so.max_num_iterations = 200;
  so.function_tolerance = 1e-14;
  so.parameter_tolerance = 1e-14;
  so.gradient_tolerance = 1e-16;
  so.num_threads = 1;
  so.logging_type = ceres::SILENT;
  return so;
}
}  // namespace

namespace {

// The fitted model's pins against the detected ones: sets fit->rms_px and fit->max_px, returns the squared sum.
double score_fitted_pins(const std::vector<Vec2>& pins_px, double dome_radius_m, double pin_depth_m,
                         TactipGeometryFit* fit) {
  double sse = 0;
  for (std::size_t j = 0; j < pins_px.size(); ++j) {
    const TactipPinSite& site = fit->rings.sites[j];
    if (site.ring < 0) continue;
    const Vec2 model_px =
        tactip_pin_px(fit->camera, dome_radius_m, pin_depth_m, fit->ring_pitch_rad, fit->azimuth_rad, site);
    const double e = (model_px - pins_px[j]).norm();
    sse += e * e;
    fit->max_px = std::max(fit->max_px, e);
  }
  fit->rms_px = std::sqrt(sse / fit->pins_used);
  return sse;
}

}  // namespace

TactipGeometryFit fit_tactip_geometry(const std::vector<Vec2>& pins_px, const TactipGeometryFitOptions& options,
                                      const std::string& where) {
  const Camera& c0 = options.initial;
  if (!c0.pinhole() || !(c0.focal_px > 0) || !(c0.distance_m > 0))
    throw InputError(where,
                     "the TacTip geometry fit starts from a pinhole camera with focal_px > 0 and distance_m > 0");
  const double R = options.dome_radius_m, rp = R - options.pin_depth_m;
  if (!(R > 0) || !(options.pin_depth_m >= 0) || !(rp > 0))
    throw InputError(where, "the TacTip geometry fit needs a dome radius > 0 and 0 <= pin depth < radius");
  TactipGeometryFit fit;
  fit.rings = assign_tactip_rings(pins_px, where);
  if (!options.fit_ring_pitch && !(options.ring_pitch_rad > 0))
    throw InputError(where, "the TacTip geometry fit with a fixed ring pitch needs ring_pitch_rad > 0");
  // theta from ring 1 under the starting camera, to first order: rho_1 = f rp theta / (D - R + rp).
  const double theta0 = options.fit_ring_pitch
                            ? fit.rings.ring_radius_px[1] * (c0.distance_m - R + rp) / (c0.focal_px * rp)
                            : options.ring_pitch_rad;
  std::array<double, kParams> x{fit.rings.centre_px.x(),
                                fit.rings.centre_px.y(),
                                fit.rings.azimuth_rad,
                                theta0,
                                c0.focal_px,
                                c0.distance_m,
                                c0.k1};
  ceres::Problem problem;
  std::vector<double*> blocks;
  blocks.reserve(x.size());
  for (double& v : x) blocks.push_back(&v);
  for (std::size_t j = 0; j < pins_px.size(); ++j) {
    const TactipPinSite& site = fit.rings.sites[j];
    if (site.ring < 0) continue;
    auto* cost = new ceres::DynamicAutoDiffCostFunction<PinResidual, kParams>(new PinResidual(pins_px[j], R, rp, site));
    for (int k = 0; k < kParams; ++k) cost->AddParameterBlock(1);
    cost->SetNumResiduals(2);
    problem.AddResidualBlock(cost, nullptr, blocks);
    ++fit.pins_used;
  }
  const bool free[kParams] = {
      true, true, true, options.fit_ring_pitch, options.fit_focal, options.fit_distance, options.fit_k1};
  for (int k = 0; k < kParams; ++k)
    if (!free[k]) problem.SetParameterBlockConstant(blocks[k]);
  // The pins stay in front of the camera and the ring pitch positive.
  problem.SetParameterLowerBound(blocks[kTheta], 0, 1e-6);
  problem.SetParameterLowerBound(blocks[kDistance], 0, R - rp + 1e-6);
  problem.SetParameterLowerBound(blocks[kFocal], 0, 1e-6);
  ceres::Solver::Summary summary;
  ceres::Solve(pin_fit_solver_options(), &problem, &summary);
  fit.termination = ceres::TerminationTypeToString(summary.termination_type);
  for (double v : x)
    if (!std::isfinite(v) || summary.termination_type == ceres::FAILURE)
      throw InputError(where, "the TacTip geometry fit did not converge (" + summary.message + ")");

  fit.camera = c0;
  fit.camera.principal_px = Vec2(x[kCu], x[kCv]);
  fit.camera.focal_px = x[kFocal];
  fit.camera.distance_m = x[kDistance];
  fit.camera.k1 = x[kK1];
  fit.azimuth_rad = x[kPhi0];
  fit.ring_pitch_rad = x[kTheta];
  const double sse = score_fitted_pins(pins_px, R, options.pin_depth_m, &fit);

  // Covariance of the free parameters: (J^T J)^-1 times the residual variance, J the Jacobian at the optimum
  // with its columns scaled to unit norm for the rank test (f in px and D in metres differ by 1e4).
  const double nan = std::numeric_limits<double>::quiet_NaN();
  double* sigma_out[kParams] = {
      &fit.sigma_principal_px.x(), &fit.sigma_principal_px.y(), nullptr,      &fit.sigma_pitch_rad,
      &fit.sigma_focal_px,         &fit.sigma_distance_m,       &fit.sigma_k1};
  for (double* s : sigma_out)
    if (s) *s = nan;
  ceres::Problem::EvaluateOptions eo;
  std::vector<int> free_index;
  for (int k = 0; k < kParams; ++k)
    if (free[k]) {
      eo.parameter_blocks.push_back(blocks[k]);
      free_index.push_back(k);
    }
  const int p = int(free_index.size()), dof = 2 * fit.pins_used - p;
  ceres::CRSMatrix crs;
  problem.Evaluate(eo, nullptr, nullptr, nullptr, &crs);
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(crs.num_rows, crs.num_cols);
  for (int r = 0; r < crs.num_rows; ++r)
    for (int e = crs.rows[r]; e < crs.rows[r + 1]; ++e) J(r, crs.cols[e]) = crs.values[e];
  const Eigen::VectorXd scale = J.colwise().norm().transpose();
  if (dof > 0 && scale.minCoeff() > 0) {
    const Eigen::MatrixXd Js = J * scale.cwiseInverse().asDiagonal();
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(Js.transpose() * Js);
    fit.covariance_rcond = eig.eigenvalues().minCoeff() / eig.eigenvalues().maxCoeff();
    if (fit.covariance_rcond > kMinCovarianceRcond) {
      fit.covariance_ok = true;
      const Eigen::MatrixXd inv = eig.eigenvectors() * eig.eigenvalues().cwiseInverse().asDiagonal() *
                                  eig.eigenvectors().transpose();
      const double variance = sse / dof;
      for (int q = 0; q < p; ++q)
        if (sigma_out[free_index[q]]) *sigma_out[free_index[q]] = std::sqrt(inv(q, q) * variance) / scale(q);
    }
  }
  return fit;
}

}  // namespace sb
