// lens_distortion's fingerprint (fingerprint_lens.hpp).
#include "core/loop/fingerprint_lens.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "core/loop/rest_grid_lens.hpp"

namespace sb {

Vec2 lens_k1_pattern(const Camera& camera, const Vec2& m_px, const Vec2& d_px) {
  const double hd2 = 0.25 * (double(camera.width_px) * camera.width_px + double(camera.height_px) * camera.height_px);
  const auto k1_term = [&](const Vec2& p) {
    const Vec2 q = p - camera.principal_px;
    return Vec2(q * (q.squaredNorm() / hd2));
  };
  return k1_term(m_px + d_px) - k1_term(m_px);
}

namespace {

// The undistorted displacement u with D(m + u) - D(m) = d for radial distortion k1 (k2 = 0): the image
// point t = D(m) + d lies on the ray of q = m + u - c, |q| (1 + k1 |q|^2 / hd^2) = |t - c| (Newton).
Vec2 lens_undistort(const Camera& camera, double k1, const Vec2& m, const Vec2& d) {
  if (k1 == 0.0) return d;
  const double hd2 = 0.25 * (double(camera.width_px) * camera.width_px + double(camera.height_px) * camera.height_px);
  const Vec2 qm = m - camera.principal_px;
  const Vec2 t = qm * (1 + k1 * qm.squaredNorm() / hd2) + d;
  const double target = t.norm();
  if (target == 0.0) return -qm;
  double s = target;
  for (int it = 0; it < 20; ++it) {
    const double f = s * (1 + k1 * s * s / hd2) - target, df = 1 + 3 * k1 * s * s / hd2;
    if (!(df > 0)) break;
    s -= f / df;
    if (std::abs(f) < 1e-13 * target) break;
  }
  return t / target * s - qm;
}

// Per frame, the nuisance fields a contact model's error of a press or twist can hold (lens_fingerprint):
// 2 n_hat symmetric fields about the contact centre, a uniform translation, and the field scaled near the
// gel's sides.
Eigen::MatrixXd lens_nuisance(const Sensor& sensor, const Vec2& centre_px, double pitch_px,
                              const std::vector<Vec2>& field_px) {
  const std::size_t M = sensor.markers_rest_px.size();
  double reach = 0;
  for (const Vec2& m : sensor.markers_rest_px) reach = std::max(reach, (m - centre_px).norm());
  const int hats = static_cast<int>(std::ceil(reach / pitch_px)) + 1;
  const std::vector<double> side_lengths = {0.5 * sensor.gel.thickness_m, sensor.gel.thickness_m};
  Eigen::MatrixXd N = Eigen::MatrixXd::Zero(2 * static_cast<Eigen::Index>(M), 2 * hats + 2 + 2 * side_lengths.size());
  const Vec2 half = 0.5 * sensor.gel.size_m;
  for (std::size_t j = 0; j < M; ++j) {
    const auto r = 2 * static_cast<Eigen::Index>(j);
    const Vec2 out = sensor.markers_rest_px[j] - centre_px;
    const double rho = out.norm();
    const Vec2 radial = rho > 1e-9 ? Vec2(out / rho) : Vec2(1, 0), tangential(-radial.y(), radial.x());
    for (int b = 0; b < hats; ++b) {
      const double w = std::max(0.0, 1.0 - std::abs(rho / pitch_px - b));
      const Eigen::Index col = 2 * Eigen::Index{b};
      N.block<2, 1>(r, col) = w * radial;
      N.block<2, 1>(r, col + 1) = w * tangential;
    }
    const Eigen::Index shift_col = 2 * Eigen::Index{hats};
    N(r, shift_col) = 1;
    N(r + 1, shift_col + 1) = 1;
    const Vec2 p = sensor.p_EM[j].head<2>();
    const double dx = half.x() - std::abs(p.x()), dy = half.y() - std::abs(p.y());
    const Vec2 normal = dx < dy ? Vec2(1, 0) : Vec2(0, 1);
    const Vec2 f = field_px[j].allFinite() ? field_px[j] : Vec2::Zero();
    Eigen::Index col = 2 * hats + 2;
    for (double l : side_lengths) {
      const double w = std::exp(-std::max(0.0, std::min(dx, dy)) / l);
      N.block<2, 1>(r, col++) = w * f;
      N.block<2, 1>(r, col++) = w * normal * normal.dot(f);
    }
  }
  return N;
}

}  // namespace

LensFingerprint lens_fingerprint(const Sensor& sensor, const std::vector<FingerprintSample>& samples) {
  const std::size_t M = sensor.markers_rest_px.size();
  for (const auto& s : samples) {
    require_fingerprint_flags(s, "lens_fingerprint");
    if (s.pred_px.size() != s.meas_px.size() || s.contact_centre_px.size() != s.meas_px.size() ||
        s.travel_px.size() != s.meas_px.size())
      throw std::invalid_argument(
          "lens_fingerprint: need the model's field, the contact centre and its travel per frame");
  }
  const double pitch = marker_pitch_px(sensor);
  constexpr double kUntravelledPx = 0.5;
  // The regression at a trial k1. The regressor is the pattern of the measured field undistorted by k1 (the
  // lens acts on the true field, which the measurement holds better than a model with a form error); its
  // instrument is the pattern of the model's field, which does not share the measurement's noise (the
  // noise in both sides of a plain regression would bias k1 by sigma^2 tr(P dg/dd) / |P g|^2).
  struct Sums {
    double ez = 0, gz = 0, zz = 0, gg = 0, values = 0, nuisance = 0, frames = 0;
    std::vector<Eigen::VectorXd> e, g;  // per frame, the asymmetric parts (for the residual's scatter)
  };
  const auto regress = [&](double k1) {
    Sums t;
    for (const auto& s : samples)
      for (std::size_t k = 0; k < s.meas_px.size(); ++k) {
        if (!s.in_contact[k] || !(s.travel_px[k] < kUntravelledPx) || !frame_moved(s.meas_px[k])) continue;
        Eigen::VectorXd e = Eigen::VectorXd::Zero(2 * M), g = e, z = e;
        std::vector<Vec2> u(M, Vec2::Zero());
        std::vector<bool> seen(M, false);
        for (std::size_t j = 0; j < M; ++j) {
          const Vec2 &d = s.meas_px[k][j], &p = s.pred_px[k][j];
          if (!d.allFinite() || !p.allFinite()) continue;
          seen[j] = true;
          u[j] = lens_undistort(sensor.camera, k1, sensor.markers_rest_px[j], d);
          e.segment<2>(2 * j) = d - p;
          g.segment<2>(2 * j) = lens_k1_pattern(sensor.camera, sensor.markers_rest_px[j], u[j]);
          z.segment<2>(2 * j) = lens_k1_pattern(sensor.camera, sensor.markers_rest_px[j], p);
          t.values += 2;
        }
        Eigen::MatrixXd N = lens_nuisance(sensor, s.contact_centre_px[k], pitch, s.pred_px[k]);
        for (std::size_t j = 0; j < M; ++j)  // lost markers carry no equation
          if (!seen[j]) N.middleRows(2 * static_cast<Eigen::Index>(j), 2).setZero();
        const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(N);
        const auto asym = [&](const Eigen::VectorXd& v) -> Eigen::VectorXd { return v - N * qr.solve(v); };
        t.e.push_back(asym(e));
        t.g.push_back(asym(g));
        const Eigen::VectorXd z_asym = asym(z);
        t.ez += t.e.back().dot(z_asym), t.gz += t.g.back().dot(z_asym), t.zz += z_asym.squaredNorm();
        t.gg += t.g.back().squaredNorm();
        t.nuisance += qr.rank();
        t.frames += 1;
      }
    return t;
  };
  LensFingerprint fp;
  Sums t = regress(0.0);
  if (t.frames == 0 || !(t.gz != 0) || !(t.zz > 0)) return fp;
  // The estimate is the fixed point k1 = F(k1), F(k) = ez / gz of regress(k): secant steps from F(0).
  double k_prev = 0.0, h_prev = t.ez / t.gz, k = std::clamp(h_prev, -1.0, 1.0);
  for (int it = 0; it < 12; ++it) {
    t = regress(k);
    if (!(t.gz != 0)) return fp;
    const double h = t.ez / t.gz - k;
    if (std::abs(h) < 1e-9 || h == h_prev) break;
    const double next = k - h * (k - k_prev) / (h - h_prev);
    k_prev = k, h_prev = h, k = std::clamp(next, -1.0, 1.0);
  }
  fp.k1 = t.ez / t.gz;
  fp.frames = t.frames;
  double rr = 0;
  for (std::size_t f = 0; f < t.e.size(); ++f) rr += (t.e[f] - fp.k1 * t.g[f]).squaredNorm();
  const double dof = std::max(1.0, t.values - t.nuisance - 1);
  fp.k1_stderr = std::sqrt(rr / dof * t.zz) / std::abs(t.gz);
  fp.signal_rms_px = std::abs(fp.k1) * std::sqrt(2 * t.gg / t.values);
  return fp;
}

namespace {

std::string lens_missing(const LensFingerprint& f, const FingerprintRules& r) {
  if (!std::isfinite(f.k1)) return "no frame of a press or twist in contact";
  if (!(std::abs(f.k1) >= r.min_k1))
    return "k1 " + estimate_text(f.k1) + " is none (|k1| < " + estimate_text(r.min_k1) + ")";
  if (!(std::abs(f.k1) >= r.k1_sigmas * f.k1_stderr))
    return "k1 " + estimate_text(f.k1) + " within " + estimate_text(r.k1_sigmas) + " standard errors of 0";
  if (!(std::abs(f.k1) < 1)) return "k1 " + estimate_text(f.k1) + " outside the lens range";
  return "";
}

// The rest grid's lens: one estimate for both splits (the rest positions are the sensor's).
std::string rest_grid_missing(const RestGridLens& g, const FingerprintRules& r) {
  if (!(std::abs(g.k1) >= r.min_k1)) return "k1 is none (|k1| < " + estimate_text(r.min_k1) + ")";
  if (!(std::abs(g.k1) >= r.k1_sigmas * g.k1_stderr))
    return "k1 within " + estimate_text(r.k1_sigmas) + " standard errors of 0";
  if (!(std::abs(g.k1) < 1)) return "k1 outside the lens range";
  return "";
}

FingerprintCheck check_rest_grid_lens(const RestGridLens& g, const FingerprintRules& r) {
  FingerprintCheck c;
  c.evidence = "the rest grid, a printed lattice bent by the lens (the same on both splits)";
  c.param = "k1";
  c.calibration = c.validation = g.k1;
  c.signal_px = g.shift_rms_px;
  c.beyond_model_form = true;
  c.acceptance = FingerprintCheck::Acceptance::kEvidence;
  const std::string missing = rest_grid_missing(g, r);
  c.verdict = "rest grid: " + describe(g) + (missing.empty() ? ": found" : ": not found, " + missing);
  c.consistent = missing.empty();
  c.held = {{"k1", g.k1}, {"k2", 0.0}};
  return c;
}

FingerprintCheck check_lens(const LensFingerprint& cal, const LensFingerprint& val, const FingerprintRules& r,
                            const RestGridLens& grid) {
  FingerprintCheck c;
  c.evidence = "residual not symmetric about the contact (presses and twists; the rest grid is " + describe(grid) + ")";
  c.param = "k1";
  c.calibration = cal.k1, c.validation = val.k1;
  c.signal_px = cal.signal_rms_px;
  conclude_finding(&c, lens_missing(cal, r), lens_missing(val, r), splits_agree(cal.k1, val.k1, r.agreement), r);
  c.held = {{"k2", 0.0}};
  c.band = {agreement_band("k1", cal.k1, r.agreement)};
  return c;
}

}  // namespace

bool lens_needs_model(const Sensor& sensor) {
  return !rest_grid_lens(sensor.camera, sensor.markers_rest_px).is_lattice;
}
FingerprintCheck lens_check(const Sensor& sensor, const std::vector<FingerprintSample>& calibration,
                            const std::vector<FingerprintSample>& validation, const FingerprintRules& rules) {
  const RestGridLens grid = rest_grid_lens(sensor.camera, sensor.markers_rest_px);
  if (grid.is_lattice) return check_rest_grid_lens(grid, rules);
  return check_lens(lens_fingerprint(sensor, calibration), lens_fingerprint(sensor, validation), rules, grid);
}

}  // namespace sb
