#include "core/calibration/metrics.hpp"

#include <algorithm>

#include <cmath>
#include <stdexcept>

namespace sb {

bool nothing_tracked(const std::vector<Vec2>& meas) {
  return !meas.empty() && std::none_of(meas.begin(), meas.end(), [](const Vec2& d) { return d.allFinite(); });
}

void MetricsAccumulator::add_frame(const std::vector<Vec2>& pred, const std::vector<Vec2>& meas) {
  if (pred.size() != meas.size())
    throw std::invalid_argument("metrics: " + std::to_string(pred.size()) + " predicted markers for " +
                                std::to_string(meas.size()) + " measured");
  bool moves = false;
  for (const Vec2& m : meas) moves = moves || (m.allFinite() && m.norm() >= kMotionThresholdPx);
  if (!moves) return;
  ++frames_;
  for (std::size_t i = 0; i < meas.size(); ++i) {
    const Vec2& m = meas[i];
    if (!m.allFinite()) continue;  // lost by the tracker
    const Vec2& p = pred[i];
    if (!p.allFinite()) {
      ++invalid_;
      continue;
    }
    sum_sq_ += (p - m).squaredNorm();
    ++n_;
    const double mn = m.norm();
    if (mn < kMotionThresholdPx) continue;
    const double pn = p.norm();
    sum_cos_ += pn < kZeroPredictionPx ? 0.0 : p.dot(m) / (pn * mn);
    ++n_cs_;
  }
}

void MetricsAccumulator::merge(const MetricsAccumulator& o) {
  sum_sq_ += o.sum_sq_;
  sum_cos_ += o.sum_cos_;
  n_ += o.n_;
  n_cs_ += o.n_cs_;
  frames_ += o.frames_;
  invalid_ += o.invalid_;
}

MetricsResult MetricsAccumulator::result() const {
  MetricsResult r;
  r.n = n_;
  r.n_cs = n_cs_;
  r.rmse_px = n_ > 0 ? std::sqrt(sum_sq_ / static_cast<double>(n_)) : std::nan("");
  r.cs = n_cs_ > 0 ? sum_cos_ / static_cast<double>(n_cs_) : std::nan("");
  return r;
}

MetricsResult frame_metrics(const std::vector<Vec2>& pred, const std::vector<Vec2>& meas) {
  MetricsAccumulator acc;
  acc.add_frame(pred, meas);
  return acc.result();
}

void MotionMetrics::add(const std::string& motion, const MetricsAccumulator& acc) {
  per_motion[motion].merge(acc);
  overall.merge(acc);
}

void MotionMetrics::merge(const MotionMetrics& other) {
  for (const auto& [motion, acc] : other.per_motion) per_motion[motion].merge(acc);
  overall.merge(other.overall);
}

}  // namespace sb
