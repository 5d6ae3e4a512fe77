#include "core/loop/release_phase.hpp"
#include "core/base/numbers.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace sb {

namespace {
constexpr double kLoadedFraction = 0.5;    // "in contact": the field is at least half its peak
constexpr double kReleasedFraction = 0.3;  // "released": below 30 % of the peak, and it stays there
constexpr int kMinReleaseFrames = 4;
// Unloading is over when a frame keeps at least this fraction of the previous frame's mean |d|: before
// that the field is still the contact's, dropping with the indenter.
constexpr double kSettledFraction = 0.8;
constexpr double kMaxTauS = 1000.0;
constexpr int kTauGridPerDecade = 40;

bool valid(const Vec2& d) { return std::isfinite(d.x()) && std::isfinite(d.y()); }

// The recovery law's factor g(t) = c + (1 - c) exp(-t / tau).
double recovery(double t, const ReleaseFit& f) { return f.permanent + (1 - f.permanent) * std::exp(-t / f.tau_s); }
}  // namespace

std::vector<double> mean_displacement_per_frame(const std::vector<std::vector<Vec2>>& disp_px) {
  std::vector<double> m;
  m.reserve(disp_px.size());
  for (const auto& frame : disp_px) {
    double sum = 0;
    int n = 0;
    for (const Vec2& d : frame)
      if (valid(d)) sum += d.norm(), ++n;
    m.push_back(n > 0 ? sum / n : kNaN);
  }
  return m;
}

ReleaseFit fit_release(const std::vector<std::vector<Vec2>>& disp_px, int t0, int first, int last, double dt_s) {
  // For a fixed tau the law is linear in c: d(t) = d0 [e + c (1 - e)], e = exp(-t / tau). Least squares
  // over every marker component: c = sum (d - d0 e) . d0 (1 - e) / sum |d0 (1 - e)|^2, clamped to [0, 1].
  ReleaseFit best;
  double best_sse = std::numeric_limits<double>::infinity();
  const double tau_min = std::max(dt_s, 1e-3);
  const int steps = static_cast<int>(std::ceil(kTauGridPerDecade * std::log10(kMaxTauS / tau_min)));
  const auto& d0 = disp_px[t0];
  for (int s = 0; s <= steps; ++s) {
    const double tau = tau_min * std::pow(10.0, static_cast<double>(s) / kTauGridPerDecade);
    double num = 0, den = 0;
    for (int k = first; k < last; ++k) {
      const double e = std::exp(-(k - t0) * dt_s / tau);
      for (std::size_t i = 0; i < d0.size() && i < disp_px[k].size(); ++i) {
        if (!valid(d0[i]) || !valid(disp_px[k][i])) continue;
        const Vec2 basis = d0[i] * (1 - e);
        num += (disp_px[k][i] - d0[i] * e).dot(basis);
        den += basis.squaredNorm();
      }
    }
    ReleaseFit f;
    f.tau_s = tau;
    f.permanent = den > 0 ? std::clamp(num / den, 0.0, 1.0) : 0.0;
    const double sse = std::pow(release_rmse(disp_px, t0, first, last, dt_s, &f), 2);
    if (sse < best_sse) {
      best_sse = sse;
      best = f;
      best.tau_at_bound = s == steps;
    }
  }
  return best;
}

double release_rmse(const std::vector<std::vector<Vec2>>& disp_px, int t0, int first, int last, double dt_s,
                    const ReleaseFit* fit) {
  double sse = 0;
  long n = 0;
  const auto& d0 = disp_px[t0];
  for (int k = first; k < last; ++k) {
    const double g = fit ? recovery((k - t0) * dt_s, *fit) : 0.0;
    for (std::size_t i = 0; i < d0.size() && i < disp_px[k].size(); ++i) {
      if (!valid(d0[i]) || !valid(disp_px[k][i])) continue;
      sse += (disp_px[k][i] - g * d0[i]).squaredNorm();
      ++n;
    }
  }
  return n > 0 ? std::sqrt(sse / n) : kNaN;  // per marker: sqrt of the mean squared vector error
}

ReleasePhase analyse_release(const std::vector<std::vector<Vec2>>& disp_px, double dt_s) {
  ReleasePhase r;
  const std::vector<double> m = mean_displacement_per_frame(disp_px);
  const int n = static_cast<int>(m.size());
  for (int k = 0; k < n; ++k)
    if (std::isfinite(m[k]) && (r.peak_frame < 0 || m[k] > r.peak_mean_px)) r.peak_frame = k, r.peak_mean_px = m[k];
  if (r.peak_frame < 0 || r.peak_mean_px <= 0) {
    r.why_not = "no marker moves";
    return r;
  }
  int last_loaded = r.peak_frame;
  for (int k = 0; k < n; ++k)
    if (std::isfinite(m[k]) && m[k] >= kLoadedFraction * r.peak_mean_px) last_loaded = k;
  int t0 = -1;
  for (int k = last_loaded + 1; k < n; ++k)
    if (std::isfinite(m[k]) && m[k] < kReleasedFraction * r.peak_mean_px) {
      t0 = k;
      break;
    }
  if (t0 < 0) {
    r.why_not = "still loaded at the end (never below 30 % of the peak after the last loaded frame)";
    return r;
  }
  while (t0 + 1 < n && std::isfinite(m[t0 + 1]) && m[t0 + 1] < kSettledFraction * m[t0]) ++t0;
  for (int k = t0; k < n; ++k)
    if (std::isfinite(m[k]) && m[k] >= kReleasedFraction * r.peak_mean_px) {
      r.why_not = "contact again after the release (frame " + std::to_string(k) + ")";
      return r;
    }
  r.frames = n - t0;
  if (r.frames < kMinReleaseFrames) {
    r.why_not = "only " + std::to_string(r.frames) + " frames after the release";
    return r;
  }
  r.found = true;
  r.release_frame = t0;
  r.left_mean_px = m[t0];
  for (const Vec2& d : disp_px[t0])
    if (valid(d)) r.left_max_px = std::max(r.left_max_px, d.norm());
  r.end_mean_px = m[n - 1];
  // Fit on the first half after t0 (t0 itself is the initial condition), score on the rest.
  const int split = t0 + 1 + (r.frames - 1) / 2;
  r.fit = fit_release(disp_px, t0, t0 + 1, split, dt_s);
  r.heldout_rmse_zero_px = release_rmse(disp_px, t0, split, n, dt_s, nullptr);
  r.heldout_rmse_fit_px = release_rmse(disp_px, t0, split, n, dt_s, &r.fit);
  ReleaseFit persist;
  persist.tau_s = 1.0;
  persist.permanent = 1.0;
  r.heldout_rmse_persist_px = release_rmse(disp_px, t0, split, n, dt_s, &persist);
  return r;
}

}  // namespace sb
