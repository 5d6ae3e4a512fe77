#pragma once
// skin_indentation's spreading kernel: how the skin spreads one pin's inward push to its neighbours, a normalised
// Gaussian over the pins' rest positions. Shared: a fit keeps a model per sample and a kernel is n x n (0.86 MB for
// the TacTip's 327 pins, 4.4 GB over the 5005 models of a 10,000-sample loop's final refit when each built its own).
// Tested in tests/test_spreading_kernel.cpp.
#include <memory>
#include <vector>

#include "core/geometry/pose.hpp"

namespace sb::effects {

using SpreadingKernel = std::vector<double>;  // n x n, row-major

// Row j: exp(-|p_EMj - p_EMk|^2 / (2 sigma^2)) over k, normalised to sum 1. @pre sigma > 0.
SpreadingKernel spreading_kernel(const std::vector<Vec3>& p_EM, double sigma);

// The kernel of these pins at this width, built once and shared by every caller while one of them holds it (then
// freed; the next call builds it again). Keyed by the pins' values, not their address. Thread-safe.
// @pre sigma > 0.
std::shared_ptr<const SpreadingKernel> shared_spreading_kernel(const std::vector<Vec3>& p_EM, double sigma);

}  // namespace sb::effects
