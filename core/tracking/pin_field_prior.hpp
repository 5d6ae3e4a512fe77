#pragma once
// A prior for the pin field of a sample whose inputs are known (e.g. the TacTip set's press depth, tilt,
// shear and twist): a per-pin linear regression of the displacement on covariates of the inputs, fitted
// on tracked samples. pin_tracker.hpp's track_pins takes the prediction and tracks only its residual, so
// the lattice's ambiguity (a field beyond half a pitch) is resolved by the inputs, not guessed.
//
// A regression fitted only on shallow presses does not know deep ones, and deep ones cannot be tracked
// without a prior: fit_prior_by_continuation walks up a difficulty (the press depth) in stages. Each stage
// tracks the not yet accepted samples up to its limit with the prior fitted so far (an extrapolation by one
// step), accepts those kept >= accept_fraction and clean under lattice_check.hpp, and refits on every
// accepted sample; refinement passes then track every sample again with the latest prior (a sample kept
// in the fit keeps its previous field when it fails the second time). Only the samples given are read: pass the
// calibration split alone.
#include <Eigen/Core>
#include <vector>

#include "core/tracking/lattice_check.hpp"
#include "core/tracking/pin_tracker.hpp"

namespace sb {

class PinFieldPrior {
 public:
  // features[k]: covariates of sample k (same length for all; include a constant); fields[k]: its tracked
  // displacement per reference pin, NaN where lost (left out of that pin's fit). A pin with fewer than
  // 2 x (number of covariates) tracked samples borrows the regression of its nearest fitted pin. Ridge
  // `ridge` x (samples of the pin) on every coefficient but the first (the constant). Throws
  // std::invalid_argument on mismatched sizes or when no pin has enough samples.
  static PinFieldPrior fit(const PinReference& ref, const std::vector<Eigen::VectorXd>& features,
                           const std::vector<std::vector<Vec2>>& fields, double ridge);
  bool empty() const { return coef_.size() == 0; }
  // Predicted displacement per reference pin (empty when the prior is empty).
  std::vector<Vec2> predict(const Eigen::VectorXd& features) const;
  int samples_used() const { return samples_used_; }

 private:
  Eigen::MatrixXd coef_;  // covariates x (2 pins): columns 2i, 2i+1 = u, v of pin i
  int samples_used_ = 0;
};

struct ContinuationOptions {
  std::vector<double> limits;     // increasing difficulty limits of the stages (the last covers every sample)
  double accept_fraction = 0.95;  // a sample joins the fit when it keeps this fraction of pins ...
  LatticeCheckOptions check;      // ... and is clean under the lattice check (against the current prior)
  double ridge = 1e-3;
  int refine_passes = 2;  // passes over every sample with the latest prior after the last stage
};

struct ContinuationStage {
  double limit = 0;
  int candidates = 0;                          // samples up to the limit not accepted before this stage
  int accepted = 0;                            // of those, accepted in this stage
  bool refine = false;                         // a refinement pass (every sample, accepted or not, tracked again)
  double miss_median_px = 0, miss_p95_px = 0;  // |tracked - prior| of the accepted samples' pins (prior before refit)
};

struct ContinuationResult {
  PinFieldPrior prior;
  std::vector<ContinuationStage> stages;
  std::vector<char> accepted;  // per sample: in the final fit
};

// detections[k], features[k], difficulty[k]: sample k.
ContinuationResult fit_prior_by_continuation(const PinReference& ref,
                                             const std::vector<std::vector<PinDetection>>& detections,
                                             const std::vector<Eigen::VectorXd>& features,
                                             const std::vector<double>& difficulty, const PinTrackerOptions& tracker,
                                             const ContinuationOptions& options);

}  // namespace sb
