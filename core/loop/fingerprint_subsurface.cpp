// subsurface_markers' fingerprint (fingerprint_subsurface.hpp).
#include "core/loop/fingerprint_subsurface.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "core/effects/effects.hpp"

namespace sb {

double grid_laplacian_energy(const Sensor& sensor, const std::vector<Vec2>& field_px) {
  if (field_px.size() != sensor.markers_rest_px.size())
    throw std::invalid_argument("grid_laplacian_energy: field has " + std::to_string(field_px.size()) +
                                " markers, the sensor " + std::to_string(sensor.markers_rest_px.size()));
  return laplacian_energy(interior_neighbours(sensor), field_px);
}

namespace {

// The grid Laplacian of a field on the interior markers, stacked (x, y per marker); lost markers give 0.
// noise_weight, when given, gains 2 (1 + 1/n) per marker whose Laplacian is defined (n its neighbours): the
// variance of white noise of unit sigma in those two components.
Eigen::VectorXd laplacian_values(const std::vector<std::vector<int>>& nb, const std::vector<Vec2>& f,
                                 double* noise_weight = nullptr) {
  Eigen::VectorXd out = Eigen::VectorXd::Zero(2 * static_cast<Eigen::Index>(f.size()));
  for (std::size_t i = 0; i < nb.size(); ++i) {
    if (nb[i].empty() || !f[i].allFinite()) continue;
    Vec2 mean = Vec2::Zero();
    bool finite = true;
    for (int j : nb[i]) {
      mean += f[static_cast<std::size_t>(j)];
      finite = finite && f[static_cast<std::size_t>(j)].allFinite();
    }
    if (!finite) continue;
    out.segment<2>(2 * static_cast<Eigen::Index>(i)) = mean / static_cast<double>(nb[i].size()) - f[i];
    if (noise_weight) *noise_weight += 2.0 * (1.0 + 1.0 / static_cast<double>(nb[i].size()));
  }
  return out;
}

}  // namespace

double tracker_noise_px(const std::vector<FingerprintSample>& samples) {
  std::vector<double> second;
  for (const auto& s : samples)
    for (std::size_t k = 1; k + 1 < s.meas_px.size(); ++k)
      for (std::size_t j = 0; j < s.meas_px[k].size(); ++j) {
        const Vec2 e = s.meas_px[k + 1][j] - 2.0 * s.meas_px[k][j] + s.meas_px[k - 1][j];
        if (!e.allFinite()) continue;
        second.push_back(std::abs(e.x()));
        second.push_back(std::abs(e.y()));
      }
  if (second.empty()) return kFingerprintNaN;
  const auto mid = second.begin() + static_cast<std::ptrdiff_t>(second.size() / 2);
  std::nth_element(second.begin(), mid, second.end());
  constexpr double kMadToSigma = 0.6744897501960817;  // median |N(0, 1)|
  return *mid / (kMadToSigma * std::sqrt(6.0));
}

SubsurfaceFingerprint subsurface_fingerprint(const Sensor& sensor, const std::vector<FingerprintSample>& samples) {
  const auto nb = interior_neighbours(sensor);
  const auto energy = [](const std::vector<Vec2>& f) {
    double e = 0;
    for (const Vec2& v : f)
      if (v.allFinite()) e += v.squaredNorm();
    return e;
  };
  std::vector<const std::vector<Vec2>*> pred;
  std::vector<Eigen::VectorXd> meas_lap;
  SubsurfaceFingerprint fp;
  double meas_total = 0, pred_total = 0;
  for (const auto& s : samples) {
    if (s.pred_px.size() != s.meas_px.size())
      throw std::invalid_argument("subsurface_fingerprint: need the model's field for every frame");
    for (std::size_t k = 0; k < s.meas_px.size(); ++k) {
      if (!frame_moved(s.meas_px[k])) continue;
      meas_lap.push_back(laplacian_values(nb, s.meas_px[k], &fp.noise_weight));
      // A lost marker: the model's value there is dropped too, so both see the same markers.
      for (std::size_t j = 0; j < s.meas_px[k].size(); ++j)
        if (!s.meas_px[k][j].allFinite()) meas_lap.back().segment<2>(2 * static_cast<Eigen::Index>(j)).setZero();
      fp.measured_energy_px2 += meas_lap.back().squaredNorm();
      fp.model_energy_px2 += laplacian_energy(nb, s.pred_px[k]);
      meas_total += energy(s.meas_px[k]);
      pred_total += energy(s.pred_px[k]);
      pred.push_back(&s.pred_px[k]);
      fp.frames += 1;
    }
  }
  if (fp.frames == 0 || !(meas_total > 0) || !(pred_total > 0)) return fp;
  fp.measured_fine_fraction = fp.measured_energy_px2 / meas_total;
  fp.model_fine_fraction = fp.model_energy_px2 / pred_total;
  // The misfit of the measured Laplacian by the best multiple of the smoothed model's (a gain, the effect's
  // attenuation or the model's stiffness, drops out; smooth model-form error has almost no Laplacian).
  auto smoothing = make_effect("subsurface_markers");
  EffectContext ctx;
  ctx.sensor = &sensor;
  const auto misfit = [&](double depth_m) {
    ParamSet p = smoothing->params();
    p.set("depth_m", depth_m);
    smoothing->set_params(p);
    double mm = 0, mp = 0, pp = 0;
    std::vector<Vec2> f;
    for (std::size_t i = 0; i < pred.size(); ++i) {
      f = *pred[i];
      for (std::size_t j = 0; j < f.size(); ++j)
        if (!f[j].allFinite()) f[j] = Vec2::Zero();
      smoothing->apply(ctx, f);
      Eigen::VectorXd lp = laplacian_values(nb, f);
      for (Eigen::Index r = 0; r < lp.size(); ++r)
        if (meas_lap[i](r) == 0.0) lp(r) = 0.0;  // markers the measurement has no Laplacian for
      mm += meas_lap[i].squaredNorm(), mp += meas_lap[i].dot(lp), pp += lp.squaredNorm();
    }
    return pp > 0 ? mm - mp * mp / pp : mm;
  };
  constexpr double kMaxDepthM = 0.005, kStepM = 1e-4;  // the effect's range, the scan's step
  double best = std::numeric_limits<double>::infinity(), best_h = 0;
  for (double h = 0; h <= kMaxDepthM + 1e-12; h += kStepM) {
    const double v = misfit(h);
    if (v < best) best = v, best_h = h;
  }
  // Golden-section refinement within a step either side.
  double lo = std::max(0.0, best_h - kStepM), hi = std::min(kMaxDepthM, best_h + kStepM);
  const double r = 0.5 * (std::sqrt(5.0) - 1);
  double x1 = hi - r * (hi - lo), x2 = lo + r * (hi - lo), f1 = misfit(x1), f2 = misfit(x2);
  while (hi - lo > 1e-7) {
    if (f1 < f2)
      hi = x2, x2 = x1, f2 = f1, x1 = hi - r * (hi - lo), f1 = misfit(x1);
    else
      lo = x1, x1 = x2, f1 = f2, x2 = lo + r * (hi - lo), f2 = misfit(x2);
  }
  const double refined = 0.5 * (lo + hi);
  fp.depth_m = misfit(refined) < best ? refined : best_h;
  fp.fine_misfit_px2 = misfit(fp.depth_m);
  fp.noise_px = tracker_noise_px(samples);
  return fp;
}

namespace {

// The grid-scale misfit left at the depth over the noise's own (at least rules.min_noise_px of noise).
double fine_misfit_over_noise(const SubsurfaceFingerprint& f, const FingerprintRules& r) {
  const double sigma = std::max(f.noise_px, r.min_noise_px);
  return f.noise_weight > 0 ? f.fine_misfit_px2 / (sigma * sigma * f.noise_weight) : kFingerprintNaN;
}

std::string subsurface_missing(const SubsurfaceFingerprint& f, double min_depth_m, const FingerprintRules& r) {
  if (!std::isfinite(f.depth_m)) return "no frame in which a marker moved";
  if (!(f.depth_m >= min_depth_m))
    return "the measured field is not smoother than the model's (depth " + estimate_text(1e3 * f.depth_m) + " mm < " +
           estimate_text(1e3 * min_depth_m) + " mm)";
  if (!(f.depth_m < 0.005)) return "depth at the bound (5 mm): the model's field is far sharper than any depth smooths";
  if (!std::isfinite(f.noise_px))
    return "depth " + estimate_text(1e3 * f.depth_m) +
           " mm, but no tracker noise to judge the model's grid-scale misfit "
           "against (no marker series of 3 frames), so the reading cannot be told from the model's form";
  const double over_noise = fine_misfit_over_noise(f, r);
  if (!(over_noise <= r.max_fine_misfit_over_noise))
    return "depth " + estimate_text(1e3 * f.depth_m) +
           " mm read against a model wrong at the grid scale: smoothed, it leaves " + estimate_text(over_noise) +
           "x the tracker noise's fine-scale content (> " + estimate_text(r.max_fine_misfit_over_noise) + "x; noise " +
           estimate_text(f.noise_px) + " px), so the reading is its form error as much as depth";
  return "";
}

FingerprintCheck check_subsurface(const Sensor& sensor, const SubsurfaceFingerprint& cal,
                                  const SubsurfaceFingerprint& val, const FingerprintRules& r) {
  FingerprintCheck c;
  c.evidence = "fine-scale content of the measured field against the model's";
  c.param = "depth_m";
  c.calibration = cal.depth_m, c.validation = val.depth_m;
  c.signal_px = std::sqrt(cal.measured_energy_px2 / std::max(1.0, cal.frames));
  const double min_depth = r.min_depth_fraction * marker_pitch_px(sensor) * sensor.camera.metres_per_px();
  conclude_finding(&c, subsurface_missing(cal, min_depth, r), subsurface_missing(val, min_depth, r),
                   splits_agree(cal.depth_m, val.depth_m, r.agreement), r);
  c.band = {agreement_band("depth_m", cal.depth_m, r.agreement)};
  return c;
}

}  // namespace

FingerprintCheck subsurface_check(const Sensor& sensor, const std::vector<FingerprintSample>& calibration,
                                  const std::vector<FingerprintSample>& validation, const FingerprintRules& rules) {
  return check_subsurface(sensor, subsurface_fingerprint(sensor, calibration),
                          subsurface_fingerprint(sensor, validation), rules);
}

}  // namespace sb
