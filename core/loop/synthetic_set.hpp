#pragma once
// A large set made from a small measured one (`shearbench synthesize`, bench/bench_large_set.cpp): the loop and
// `evaluate` at the size real collections come in, on data whose answer is known. Output sample k copies source
// sample k mod n: its split, motion and indenter; its path moved by one rigid jitter J_E (the same for every
// frame: X_EI' = J_E X_EI, a shift along each of E's axes and a turn about each, Gaussian); its measured field
// the model's field at the moved path plus the source's own residual (measured minus the model at the source's
// path: the structure the loop must find, where it was) plus fresh Gaussian tracker noise. The first copy of each
// source sample (k < n) is not moved, so the set holds the source's poses exactly (its field is re-noised).
#include <cstdint>
#include <string>
#include <vector>

#include "core/calibration/fit.hpp"
#include "core/loop/loop_samples.hpp"

namespace sb {

struct SyntheticSetOptions {
  std::size_t samples = 10000;  // output samples (at least the source's)
  double shift_m = 2e-4;        // standard deviation of the path's shift along each E axis (m)
  double turn_rad = 0.01;       // standard deviation of its turn about each E axis (rad)
  double noise_px = 0.1;        // tracker noise added per component (px)
  bool keep_residual = true;    // add the source's residual against the model (false: the model's field alone)
  std::uint64_t seed = 54;
};

// The jitter of output sample k (identity for k < n_source): deterministic in (seed, k).
Pose synthetic_jitter(const SyntheticSetOptions& o, std::size_t k, std::size_t n_source);

// The synthetic samples. `make` builds the model for a sample (its parameters set inside or by `params`).
// Markers the source did not measure (NaN) stay unmeasured. Ids are "<source id>~<copy>" for copies past the first.
// @pre !source.empty() and o.samples >= source.size(). Runs the model over every output sample and once over
// every source sample (in parallel).
std::vector<FitSample> synthetic_samples(const std::vector<FitSample>& source, const SampleModelFactory& make,
                                         const ParamSet& params, const SyntheticSetOptions& o);

}  // namespace sb
