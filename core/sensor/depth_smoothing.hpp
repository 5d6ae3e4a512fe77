#pragma once
// The smoothing a marker at depth h below the gel surface sees of the surface field: row-normalised Gaussian
// weights over the marker positions, w_ij = exp(-|p_i - p_j|_xy^2 / (2 h^2)) / sum_j(...), sigma = h (the
// Boussinesq/Cerruti kernels decay with sqrt(r^2 + h^2)). Used by the sensor's output stage (pins at a known
// depth) and by the subsurface_markers effect (a depth fitted to the residual).
#include <Eigen/SparseCore>
#include <vector>

#include "core/geometry/pose.hpp"

namespace sb {

// Gaussian weights beyond this many sigmas (< e^{-8} = 3e-4 of the centre weight) are dropped, which keeps
// the kernel sparse for shallow markers on dense grids.
inline constexpr double kDepthKernelCutoffSigmas = 4.0;

using DepthSmoothingWeights = Eigen::SparseMatrix<double, Eigen::RowMajor>;
// The n x n weights for markers p_EM (xy distances) at depth h > 0; every row sums to 1.
DepthSmoothingWeights depth_smoothing_weights(const std::vector<Vec3>& p_EM, double depth_m);
// The field each marker at that depth sees: row i is sum_j w_ij field_j. `field_px` has one entry per row of
// `weights` (the caller checks).
std::vector<Vec2> depth_smoothed(const DepthSmoothingWeights& weights, const std::vector<Vec2>& field_px);

}  // namespace sb
