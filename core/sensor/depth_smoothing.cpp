// Row-normalised, truncated Gaussian smoothing weights over the marker positions (depth_smoothing.hpp).
#include "core/sensor/depth_smoothing.hpp"

#include <cmath>

namespace sb {

DepthSmoothingWeights depth_smoothing_weights(const std::vector<Vec3>& p_EM, double h) {
  const auto n = static_cast<Eigen::Index>(p_EM.size());
  const double cutoff2 = kDepthKernelCutoffSigmas * kDepthKernelCutoffSigmas * h * h;
  std::vector<Eigen::Triplet<double>> entries;
  for (Eigen::Index i = 0; i < n; ++i) {
    const std::size_t row_start = entries.size();
    double row_sum = 0.0;
    for (Eigen::Index j = 0; j < n; ++j) {
      const double r2 = (p_EM[i] - p_EM[j]).head<2>().squaredNorm();
      if (r2 > cutoff2) continue;
      const double w = std::exp(-r2 / (2.0 * h * h));
      entries.emplace_back(i, j, w);
      row_sum += w;
    }
    for (std::size_t k = row_start; k < entries.size(); ++k)  // the diagonal keeps row_sum >= 1
      entries[k] = Eigen::Triplet<double>(entries[k].row(), entries[k].col(), entries[k].value() / row_sum);
  }
  DepthSmoothingWeights weights(n, n);
  weights.setFromTriplets(entries.begin(), entries.end());
  return weights;
}

std::vector<Vec2> depth_smoothed(const DepthSmoothingWeights& weights, const std::vector<Vec2>& field_px) {
  std::vector<Vec2> smoothed(field_px.size(), Vec2::Zero());
  for (Eigen::Index i = 0; i < weights.rows(); ++i)
    for (DepthSmoothingWeights::InnerIterator it(weights, i); it; ++it)
      smoothed[static_cast<std::size_t>(i)] += it.value() * field_px[static_cast<std::size_t>(it.col())];
  return smoothed;
}

}  // namespace sb
