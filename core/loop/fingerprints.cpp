// Fingerprints of effects (see fingerprints.hpp and docs/effects.md, "Fingerprints").
#include "core/loop/fingerprints.hpp"
#include "core/base/format.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <stdexcept>
#include <string_view>

#include "core/effects/effects.hpp"
#include "core/loop/rest_grid_lens.hpp"

namespace sb {

namespace {

// Minimises f over a box by a grid (n0 x n1 points, corners included) and then a pattern search that halves
// its step until it is below `tol` of the cell. Deterministic; ties keep the earlier point.
struct Box2 {
  double lo0, hi0, lo1, hi1;
};
std::pair<double, double> minimise_2d(const std::function<double(double, double)>& f, const Box2& box, int n0, int n1,
                                      double tol = 1e-3) {
  double best = std::numeric_limits<double>::infinity(), b0 = box.lo0, b1 = box.lo1;
  for (int i = 0; i < n0; ++i)
    for (int j = 0; j < n1; ++j) {
      const double x0 = box.lo0 + (box.hi0 - box.lo0) * i / (n0 - 1);
      const double x1 = box.lo1 + (box.hi1 - box.lo1) * j / (n1 - 1);
      const double v = f(x0, x1);
      if (v < best) best = v, b0 = x0, b1 = x1;
    }
  double s0 = (box.hi0 - box.lo0) / (n0 - 1), s1 = (box.hi1 - box.lo1) / (n1 - 1);
  const double min0 = tol * s0;
  while (s0 > min0) {
    bool moved = false;
    for (const auto& [d0, d1] : {std::pair{s0, 0.0}, {-s0, 0.0}, {0.0, s1}, {0.0, -s1}}) {
      const double x0 = std::clamp(b0 + d0, box.lo0, box.hi0), x1 = std::clamp(b1 + d1, box.lo1, box.hi1);
      const double v = f(x0, x1);
      if (v < best) best = v, b0 = x0, b1 = x1, moved = true;
    }
    if (!moved) s0 *= 0.5, s1 *= 0.5;
  }
  return {b0, b1};
}

// The creep evidence of one sample: which frames count and on which markers (fixed by the data), then the
// sum of squares of the evidence for a glassy field d.
struct CreepTerms {
  double held = 0, release = 0, held_count = 0, release_count = 0;
};

class CreepEvidence {
 public:
  explicit CreepEvidence(const FingerprintSample& s) : s_(s) {
    const std::size_t K = s.meas_px.size(), M = K ? s.meas_px.front().size() : 0;
    moved_.assign(M, 0);
    for (std::size_t k = 0; k < K; ++k)
      if (s.in_contact[k])
        for (std::size_t j = 0; j < M; ++j)
          moved_[j] |= s.meas_px[k][j].allFinite() && s.meas_px[k][j].norm() >= kMotionThresholdPx;
  }

  // Runs the inverse filter (as sls_glassy_field) and sums the evidence on the way.
  CreepTerms terms(double tau_s, double c) const {
    CreepTerms t;
    const auto& meas = s_.meas_px;
    const std::size_t K = meas.size(), M = moved_.size();
    const double a = std::exp(-s_.dt_s / tau_s);
    x_.assign(M, Vec2::Zero());
    last_.assign(M, Vec2::Zero());
    run_start_.assign(M, Vec2::Zero());
    release_start_.assign(M, Vec2::Zero());
    start_active_.assign(M, 0);
    bool touched = false;
    for (std::size_t k = 0; k < K; ++k) {
      touched = touched || s_.in_contact[k];
      const bool held = k > 0 && s_.held[k];
      const bool opens_run = held && !s_.held[k - 1];
      const bool released = touched && !s_.in_contact[k];
      const bool opens_release = released && k > 0 && s_.in_contact[k - 1];
      for (std::size_t j = 0; j < M; ++j) {
        if (k > 0) x_[j] = c * last_[j] * (1 - a) + a * x_[j];
        if (opens_run) {  // the run starts at the previous frame: its glassy value is last_
          run_start_[j] = last_[j];
          start_active_[j] = meas[k - 1][j].allFinite() && meas[k - 1][j].norm() >= kMotionThresholdPx;
        }
        const Vec2 d = meas[k][j] - x_[j];
        if (!d.allFinite()) continue;
        if (opens_release) release_start_[j] = d;
        last_[j] = d;
        if (held && start_active_[j]) {
          t.held += (d - run_start_[j]).squaredNorm();
          t.held_count += 1;
        } else if (released && moved_[j]) {
          t.release += (d - release_start_[j]).squaredNorm();
          t.release_count += 1;
        }
      }
    }
    return t;
  }

 private:
  const FingerprintSample& s_;
  std::vector<std::uint8_t> moved_;  // markers the load moved >= kMotionThresholdPx while in contact
  mutable std::vector<Vec2> x_, last_, run_start_, release_start_;  // scratch
  mutable std::vector<std::uint8_t> start_active_;
};

// A frame counts for the field's shape when some measured marker moved (the metric's rule).
bool frame_moved(const std::vector<Vec2>& meas_px) {
  for (const Vec2& d : meas_px)
    if (d.allFinite() && d.norm() >= kMotionThresholdPx) return true;
  return false;
}

// The smallest distance between two markers' rest positions (px): the grid pitch.
double marker_pitch_px(const Sensor& sensor) {
  const auto& m = sensor.markers_rest_px;
  double pitch = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < m.size(); ++i)
    for (std::size_t j = i + 1; j < m.size(); ++j) pitch = std::min(pitch, (m[i] - m[j]).norm());
  if (!std::isfinite(pitch) || pitch <= 0) throw std::invalid_argument("fingerprint: need two distinct markers");
  return pitch;
}

// The lattice neighbours of each interior marker (those within 1.2 pitches, on markers that have as many
// as the best-surrounded one: 4 on a square grid); empty lists for the others.
std::vector<std::vector<int>> interior_neighbours(const Sensor& sensor) {
  const auto& m = sensor.markers_rest_px;
  const double reach = 1.2 * marker_pitch_px(sensor);
  std::vector<std::vector<int>> nb(m.size());
  std::size_t most = 0;
  for (std::size_t i = 0; i < m.size(); ++i) {
    for (std::size_t j = 0; j < m.size(); ++j)
      if (i != j && (m[i] - m[j]).norm() < reach) nb[i].push_back(static_cast<int>(j));
    most = std::max(most, nb[i].size());
  }
  for (auto& list : nb)
    if (list.size() < most) list.clear();
  return nb;
}

double laplacian_energy(const std::vector<std::vector<int>>& nb, const std::vector<Vec2>& f) {
  double e = 0;
  for (std::size_t i = 0; i < nb.size(); ++i) {
    if (nb[i].empty() || !f[i].allFinite()) continue;
    Vec2 mean = Vec2::Zero();
    bool finite = true;
    for (int j : nb[i]) {
      mean += f[static_cast<std::size_t>(j)];
      finite = finite && f[static_cast<std::size_t>(j)].allFinite();
    }
    if (finite) e += (mean / static_cast<double>(nb[i].size()) - f[i]).squaredNorm();
  }
  return e;
}

void require_flags(const FingerprintSample& s, const char* who) {
  if (s.in_contact.size() != s.meas_px.size() || s.held.size() != s.meas_px.size())
    throw std::invalid_argument(std::string(who) + ": need one contact and one held flag per frame (" +
                                std::to_string(s.meas_px.size()) + " frames, " + std::to_string(s.in_contact.size()) +
                                " and " + std::to_string(s.held.size()) + " flags)");
}

}  // namespace

// ------------------------------------------------------------------------------------------ creep

std::vector<std::vector<Vec2>> sls_glassy_field(const std::vector<std::vector<Vec2>>& meas_px, double dt_s,
                                                double tau_s, double creep_fraction) {
  if (!(tau_s > 0) || !(dt_s >= 0)) throw std::invalid_argument("sls_glassy_field: need tau > 0 and dt >= 0");
  std::vector<std::vector<Vec2>> d(meas_px.size());
  if (meas_px.empty()) return d;
  const std::size_t M = meas_px.front().size();
  const double a = std::exp(-dt_s / tau_s), c = creep_fraction;
  std::vector<Vec2> x(M, Vec2::Zero()), last(M, Vec2::Zero());  // delayed part, last finite glassy value
  for (std::size_t k = 0; k < meas_px.size(); ++k) {
    if (meas_px[k].size() != M) throw std::invalid_argument("sls_glassy_field: frames with different marker counts");
    d[k].resize(M);
    for (std::size_t j = 0; j < M; ++j) {
      if (k > 0) x[j] = c * last[j] * (1 - a) + a * x[j];
      d[k][j] = meas_px[k][j] - x[j];
      if (d[k][j].allFinite()) last[j] = d[k][j];
    }
  }
  return d;
}

CreepFingerprint creep_fingerprint(const std::vector<FingerprintSample>& samples) {
  for (const auto& s : samples) require_flags(s, "creep_fingerprint");
  std::vector<CreepEvidence> per_sample;
  per_sample.reserve(samples.size());
  for (const auto& s : samples) per_sample.emplace_back(s);
  const auto evidence = [&](double tau, double c) {
    CreepTerms sum;
    for (const auto& e : per_sample) {
      const CreepTerms t = e.terms(tau, c);
      sum.held += t.held, sum.release += t.release, sum.held_count += t.held_count,
          sum.release_count += t.release_count;
    }
    return sum;
  };
  CreepFingerprint fp;
  const CreepTerms raw = evidence(1.0, 0.0);  // c = 0: the glassy field is the measured one
  fp.marker_frames = raw.held_count + raw.release_count;
  if (fp.marker_frames == 0) return fp;
  fp.signal_rms_px = std::sqrt((raw.held + raw.release) / fp.marker_frames);
  fp.held_rms_px = raw.held_count > 0 ? std::sqrt(raw.held / raw.held_count) : 0.0;
  fp.release_rms_px = raw.release_count > 0 ? std::sqrt(raw.release / raw.release_count) : 0.0;
  if (raw.held + raw.release <= 0) return fp;
  // The effect's ranges: log tau in [0.01, 10] s, c in [-0.5, 1].
  const auto cost = [&](double log_tau, double c) {
    const CreepTerms t = evidence(std::exp(log_tau), c);
    return t.held + t.release;
  };
  const auto [log_tau, c] = minimise_2d(cost, {std::log(0.01), std::log(10.0), -0.5, 1.0}, 31, 31);
  fp.tau_s = std::exp(log_tau);
  fp.creep_fraction = c;
  fp.explained_pct = 100.0 * (1.0 - cost(log_tau, c) / (raw.held + raw.release));
  return fp;
}

// ------------------------------------------------------------------------------------------- lens

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
    require_flags(s, "lens_fingerprint");
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

// ------------------------------------------------------------------------------------- subsurface

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

// ------------------------------------------------------------------------------ the finding

namespace {

// One sign and a ratio within `agreement`.
bool agree(double a, double b, double agreement) {
  if (!(std::isfinite(a) && std::isfinite(b)) || a == 0 || b == 0 || (a > 0) != (b > 0)) return false;
  return std::max(a / b, b / a) <= agreement;
}

std::string number(double v) { return format_number(v, "%.3g", "nan"); }

// The estimate and the values within `agreement` of it (its sign kept).
FingerprintCheck::Band band(const std::string& name, double estimate, double agreement) {
  const double a = estimate / agreement, b = estimate * agreement;
  return {name, estimate, std::min(a, b), std::max(a, b)};
}

// "found on both splits and agreeing", or what was missing, for the report.
void conclude(FingerprintCheck* c, const std::string& missing_cal, const std::string& missing_val, bool agreeing,
              const FingerprintRules& rules) {
  if (!missing_cal.empty())
    c->verdict = "calibration: " + missing_cal;
  else if (!missing_val.empty())
    c->verdict = "validation: " + missing_val;
  else if (!agreeing)
    c->verdict = "the splits disagree (" + number(c->calibration) + " vs " + number(c->validation) + ", more than x" +
                 number(rules.agreement) + ")";
  else
    c->verdict = "found on both splits";
  c->consistent = missing_cal.empty() && missing_val.empty() && agreeing;
}

// Log-range distance from the creep fingerprint's search box: an estimate on its edge is not a finding.
bool tau_inside(double tau) { return tau > 0.0105 && tau < 9.5; }

std::string creep_missing(const CreepFingerprint& f, const FingerprintRules& r) {
  if (!(f.signal_rms_px >= r.min_signal_px))
    return "no drift while held or after release above noise (" + number(f.signal_rms_px) + " px < " +
           number(r.min_signal_px) + " px)";
  if (!(f.explained_pct >= r.min_explained_pct))
    return "a standard linear solid explains " + number(f.explained_pct) + " % of the drift (< " +
           number(r.min_explained_pct) + " %)";
  if (!(std::abs(f.creep_fraction) >= r.min_creep_fraction))
    return "creep fraction " + number(f.creep_fraction) + " is none";
  if (!tau_inside(f.tau_s)) return "tau " + number(f.tau_s) + " s at the edge of [0.01, 10] s";
  return "";
}

FingerprintCheck check_creep(const CreepFingerprint& cal, const CreepFingerprint& val, const FingerprintRules& r) {
  FingerprintCheck c;
  c.evidence = "change of the field while held and after release";
  c.param = "tau_s";
  c.calibration = cal.tau_s, c.validation = val.tau_s;
  c.signal_px = cal.signal_rms_px;
  c.beyond_model_form = true;
  const bool agreeing = agree(cal.tau_s, val.tau_s, r.agreement) &&
                        agree(cal.creep_fraction, val.creep_fraction, r.agreement);
  conclude(&c, creep_missing(cal, r), creep_missing(val, r), agreeing, r);
  c.held = {{"tau_s", cal.tau_s}, {"creep_fraction", cal.creep_fraction}};
  return c;
}

std::string lens_missing(const LensFingerprint& f, const FingerprintRules& r) {
  if (!std::isfinite(f.k1)) return "no frame of a press or twist in contact";
  if (!(std::abs(f.k1) >= r.min_k1)) return "k1 " + number(f.k1) + " is none (|k1| < " + number(r.min_k1) + ")";
  if (!(std::abs(f.k1) >= r.k1_sigmas * f.k1_stderr))
    return "k1 " + number(f.k1) + " within " + number(r.k1_sigmas) + " standard errors of 0";
  if (!(std::abs(f.k1) < 1)) return "k1 " + number(f.k1) + " outside the lens range";
  return "";
}

// The rest grid's lens: one estimate for both splits (the rest positions are the sensor's).
std::string rest_grid_missing(const RestGridLens& g, const FingerprintRules& r) {
  if (!(std::abs(g.k1) >= r.min_k1)) return "k1 is none (|k1| < " + number(r.min_k1) + ")";
  if (!(std::abs(g.k1) >= r.k1_sigmas * g.k1_stderr))
    return "k1 within " + number(r.k1_sigmas) + " standard errors of 0";
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
  conclude(&c, lens_missing(cal, r), lens_missing(val, r), agree(cal.k1, val.k1, r.agreement), r);
  c.held = {{"k2", 0.0}};
  c.band = {band("k1", cal.k1, r.agreement)};
  return c;
}

// The grid-scale misfit left at the depth over the noise's own (at least rules.min_noise_px of noise).
double fine_misfit_over_noise(const SubsurfaceFingerprint& f, const FingerprintRules& r) {
  const double sigma = std::max(f.noise_px, r.min_noise_px);
  return f.noise_weight > 0 ? f.fine_misfit_px2 / (sigma * sigma * f.noise_weight) : kFingerprintNaN;
}

std::string subsurface_missing(const SubsurfaceFingerprint& f, double min_depth_m, const FingerprintRules& r) {
  if (!std::isfinite(f.depth_m)) return "no frame in which a marker moved";
  if (!(f.depth_m >= min_depth_m))
    return "the measured field is not smoother than the model's (depth " + number(1e3 * f.depth_m) + " mm < " +
           number(1e3 * min_depth_m) + " mm)";
  if (!(f.depth_m < 0.005)) return "depth at the bound (5 mm): the model's field is far sharper than any depth smooths";
  if (!std::isfinite(f.noise_px))
    return "depth " + number(1e3 * f.depth_m) +
           " mm, but no tracker noise to judge the model's grid-scale misfit "
           "against (no marker series of 3 frames), so the reading cannot be told from the model's form";
  const double over_noise = fine_misfit_over_noise(f, r);
  if (!(over_noise <= r.max_fine_misfit_over_noise))
    return "depth " + number(1e3 * f.depth_m) +
           " mm read against a model wrong at the grid scale: smoothed, it leaves " + number(over_noise) +
           "x the tracker noise's fine-scale content (> " + number(r.max_fine_misfit_over_noise) + "x; noise " +
           number(f.noise_px) + " px), so the reading is its form error as much as depth";
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
  conclude(&c, subsurface_missing(cal, min_depth, r), subsurface_missing(val, min_depth, r),
           agree(cal.depth_m, val.depth_m, r.agreement), r);
  c.band = {band("depth_m", cal.depth_m, r.agreement)};
  return c;
}

}  // namespace

namespace {

// The fingerprint registry: one entry per effect that has a fingerprint, keyed by the effect's catalogue id
// (tests/test_fingerprints.cpp checks every key against the effect catalogue, so a misspelt id fails there).
// needs_model: whether the check compares the measurement with the model's field on this sensor.
struct FingerprintEntry {
  std::string_view effect_id;
  bool (*needs_model)(const Sensor& sensor);
  FingerprintCheck (*check)(const Sensor& sensor, const std::vector<FingerprintSample>& calibration,
                            const std::vector<FingerprintSample>& validation, const FingerprintRules& rules);
};

FingerprintCheck creep_check(const Sensor& /*sensor*/, const std::vector<FingerprintSample>& calibration,
                             const std::vector<FingerprintSample>& validation, const FingerprintRules& rules) {
  return check_creep(creep_fingerprint(calibration), creep_fingerprint(validation), rules);
}

// On a lattice the rest grid is the evidence (no model needed); elsewhere the residual's asymmetry.
bool lens_needs_model(const Sensor& sensor) {
  return !rest_grid_lens(sensor.camera, sensor.markers_rest_px).is_lattice;
}
FingerprintCheck lens_check(const Sensor& sensor, const std::vector<FingerprintSample>& calibration,
                            const std::vector<FingerprintSample>& validation, const FingerprintRules& rules) {
  const RestGridLens grid = rest_grid_lens(sensor.camera, sensor.markers_rest_px);
  if (grid.is_lattice) return check_rest_grid_lens(grid, rules);
  return check_lens(lens_fingerprint(sensor, calibration), lens_fingerprint(sensor, validation), rules, grid);
}

FingerprintCheck subsurface_check(const Sensor& sensor, const std::vector<FingerprintSample>& calibration,
                                  const std::vector<FingerprintSample>& validation, const FingerprintRules& rules) {
  return check_subsurface(sensor, subsurface_fingerprint(sensor, calibration),
                          subsurface_fingerprint(sensor, validation), rules);
}

constexpr FingerprintEntry kFingerprints[] = {
    {"viscoelastic_creep", [](const Sensor&) { return false; }, creep_check},
    {"lens_distortion", lens_needs_model, lens_check},
    {"subsurface_markers", [](const Sensor&) { return true; }, subsurface_check},
};

const FingerprintEntry* find_fingerprint(std::string_view effect_id) {
  for (const FingerprintEntry& e : kFingerprints)
    if (e.effect_id == effect_id) return &e;
  return nullptr;
}

}  // namespace

std::vector<std::string> fingerprinted_effects() {
  std::vector<std::string> ids;
  for (const FingerprintEntry& e : kFingerprints) ids.emplace_back(e.effect_id);
  return ids;
}

bool has_fingerprint(const std::string& effect_id) { return find_fingerprint(effect_id) != nullptr; }

bool fingerprint_needs_model(const std::string& effect_id, const Sensor& sensor) {
  const FingerprintEntry* e = find_fingerprint(effect_id);
  return e != nullptr && e->needs_model(sensor);
}

std::optional<FingerprintCheck> fingerprint_check(const std::string& effect_id, const Sensor& sensor,
                                                  const std::vector<FingerprintSample>& calibration,
                                                  const std::vector<FingerprintSample>& validation,
                                                  const FingerprintRules& rules) {
  const FingerprintEntry* e = find_fingerprint(effect_id);
  if (e == nullptr) return std::nullopt;
  return e->check(sensor, calibration, validation, rules);
}

}  // namespace sb
