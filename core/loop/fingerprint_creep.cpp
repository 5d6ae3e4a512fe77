// viscoelastic_creep's fingerprint (fingerprint_creep.hpp).
#include "core/loop/fingerprint_creep.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <stdexcept>
#include <utility>

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
  const FingerprintSample& s_;       // aliased: the sample must outlive this reader (creep_fingerprint's loop)
  std::vector<std::uint8_t> moved_;  // markers the load moved >= kMotionThresholdPx while in contact
  mutable std::vector<Vec2> x_, last_, run_start_, release_start_;  // scratch
  mutable std::vector<std::uint8_t> start_active_;
};

}  // namespace

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
  for (const auto& s : samples) require_fingerprint_flags(s, "creep_fingerprint");
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

namespace {

// Log-range distance from the creep fingerprint's search box: an estimate on its edge is not a finding.
bool tau_inside(double tau) { return tau > 0.0105 && tau < 9.5; }

std::string creep_missing(const CreepFingerprint& f, const FingerprintRules& r) {
  if (!(f.signal_rms_px >= r.min_signal_px))
    return "no drift while held or after release above noise (" + estimate_text(f.signal_rms_px) + " px < " +
           estimate_text(r.min_signal_px) + " px)";
  if (!(f.explained_pct >= r.min_explained_pct))
    return "a standard linear solid explains " + estimate_text(f.explained_pct) + " % of the drift (< " +
           estimate_text(r.min_explained_pct) + " %)";
  if (!(std::abs(f.creep_fraction) >= r.min_creep_fraction))
    return "creep fraction " + estimate_text(f.creep_fraction) + " is none";
  if (!tau_inside(f.tau_s)) return "tau " + estimate_text(f.tau_s) + " s at the edge of [0.01, 10] s";
  return "";
}

FingerprintCheck check_creep(const CreepFingerprint& cal, const CreepFingerprint& val, const FingerprintRules& r) {
  FingerprintCheck c;
  c.evidence = "change of the field while held and after release";
  c.param = "tau_s";
  c.calibration = cal.tau_s, c.validation = val.tau_s;
  c.signal_px = cal.signal_rms_px;
  c.beyond_model_form = true;
  const bool agreeing = splits_agree(cal.tau_s, val.tau_s, r.agreement) &&
                        splits_agree(cal.creep_fraction, val.creep_fraction, r.agreement);
  conclude_finding(&c, creep_missing(cal, r), creep_missing(val, r), agreeing, r);
  c.held = {{"tau_s", cal.tau_s}, {"creep_fraction", cal.creep_fraction}};
  return c;
}

}  // namespace

FingerprintCheck creep_check(const Sensor& /*sensor*/, const std::vector<FingerprintSample>& calibration,
                             const std::vector<FingerprintSample>& validation, const FingerprintRules& rules) {
  return check_creep(creep_fingerprint(calibration), creep_fingerprint(validation), rules);
}

}  // namespace sb
