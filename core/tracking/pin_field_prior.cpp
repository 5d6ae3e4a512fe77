#include "core/tracking/pin_field_prior.hpp"

#include "core/base/median.hpp"
#include "core/base/numbers.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace sb {
namespace {

int kept_count(const std::vector<Vec2>& disp) {
  int k = 0;
  for (const auto& d : disp) k += d.allFinite();
  return k;
}

// Ridge least squares for one pin over the samples where it is tracked; false when too few.
bool fit_pin(std::size_t pin, const std::vector<Eigen::VectorXd>& features,
             const std::vector<std::vector<Vec2>>& fields, double ridge, Eigen::Ref<Eigen::MatrixXd> coef) {
  const Eigen::Index f = features.front().size();
  Eigen::MatrixXd AtA = Eigen::MatrixXd::Zero(f, f), Atb = Eigen::MatrixXd::Zero(f, 2);
  int m = 0;
  for (std::size_t k = 0; k < fields.size(); ++k) {
    const Vec2& d = fields[k][pin];
    if (!d.allFinite()) continue;
    AtA.selfadjointView<Eigen::Lower>().rankUpdate(features[k]);
    Atb += features[k] * d.transpose();
    ++m;
  }
  if (m < 2 * f) return false;
  AtA = AtA.selfadjointView<Eigen::Lower>();
  for (Eigen::Index j = 1; j < f; ++j) AtA(j, j) += ridge * m;
  coef = AtA.ldlt().solve(Atb);
  return true;
}

}  // namespace

PinFieldPrior PinFieldPrior::fit(const PinReference& ref, const std::vector<Eigen::VectorXd>& features,
                                 const std::vector<std::vector<Vec2>>& fields, double ridge) {
  const std::size_t n = ref.rest_px.size();
  if (features.size() != fields.size() || features.empty())
    throw std::invalid_argument("PinFieldPrior::fit: " + std::to_string(features.size()) + " feature rows for " +
                                std::to_string(fields.size()) + " fields");
  for (std::size_t k = 0; k < fields.size(); ++k)
    if (fields[k].size() != n || features[k].size() != features.front().size())
      throw std::invalid_argument("PinFieldPrior::fit: sample " + std::to_string(k) + " has the wrong size");
  PinFieldPrior p;
  p.samples_used_ = int(fields.size());
  p.coef_.setConstant(features.front().size(), 2 * Eigen::Index(n), kNaN);
  std::vector<char> fitted(n, 0);
  for (std::size_t i = 0; i < n; ++i) fitted[i] = fit_pin(i, features, fields, ridge, p.coef_.middleCols(2 * i, 2));
  if (std::none_of(fitted.begin(), fitted.end(), [](char c) { return c; }))
    throw std::invalid_argument("PinFieldPrior::fit: no pin is tracked in enough samples");
  // A pin tracked too rarely (at the mask's edge) borrows its nearest fitted pin's regression: the field
  // is smooth over a pitch, and the tracker corrects the rest from the pin's own neighbours.
  for (std::size_t i = 0; i < n; ++i) {
    if (fitted[i]) continue;
    std::size_t best = i;
    double d2 = std::numeric_limits<double>::infinity();
    for (std::size_t j = 0; j < n; ++j)
      if (fitted[j] && (ref.rest_px[j] - ref.rest_px[i]).squaredNorm() < d2) {
        d2 = (ref.rest_px[j] - ref.rest_px[i]).squaredNorm();
        best = j;
      }
    p.coef_.middleCols(2 * i, 2) = p.coef_.middleCols(2 * best, 2);
  }
  return p;
}

std::vector<Vec2> PinFieldPrior::predict(const Eigen::VectorXd& features) const {
  if (empty()) return {};
  if (features.size() != coef_.rows())
    throw std::invalid_argument("PinFieldPrior::predict: " + std::to_string(features.size()) +
                                " covariates, fitted on " + std::to_string(coef_.rows()));
  const Eigen::VectorXd flat = coef_.transpose() * features;
  std::vector<Vec2> out(coef_.cols() / 2);
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = Vec2(flat(2 * i), flat(2 * i + 1));
  return out;
}

ContinuationResult fit_prior_by_continuation(const PinReference& ref,
                                             const std::vector<std::vector<PinDetection>>& detections,
                                             const std::vector<Eigen::VectorXd>& features,
                                             const std::vector<double>& difficulty, const PinTrackerOptions& tracker,
                                             const ContinuationOptions& o) {
  const std::size_t m = detections.size();
  if (features.size() != m || difficulty.size() != m)
    throw std::invalid_argument("fit_prior_by_continuation: per-sample inputs differ in length");
  if (o.limits.empty() || !std::is_sorted(o.limits.begin(), o.limits.end()))
    throw std::invalid_argument("fit_prior_by_continuation: stage limits must be given in increasing order");
  const std::size_t need = std::size_t(std::ceil(o.accept_fraction * double(ref.rest_px.size())));
  ContinuationResult r;
  r.accepted.assign(m, 0);
  std::vector<std::vector<Vec2>> fields(m);
  // Stages up the difficulty, then refinement passes over every sample with the prior fitted on all of
  // them (a deep sample accepted late was tracked with an extrapolated prior; tracking it again with the
  // final one can add the pins that prior missed, and a sample rejected then can pass now).
  std::vector<double> limits = o.limits;
  for (int p = 0; p < o.refine_passes; ++p) limits.push_back(std::numeric_limits<double>::infinity());
  for (std::size_t s = 0; s < limits.size(); ++s) {
    const bool refine = s >= o.limits.size();
    ContinuationStage st;
    st.limit = limits[s];
    st.refine = refine;
    std::vector<double> miss;
    for (std::size_t k = 0; k < m; ++k) {
      if ((r.accepted[k] && !refine) || difficulty[k] > limits[s]) continue;
      ++st.candidates;
      const std::vector<Vec2> prior = r.prior.predict(features[k]);
      const std::vector<Vec2> tracked = track_pins(ref, detections[k], tracker, prior);
      const LatticeCheckResult check = check_lattice(ref, tracked, detections[k], o.check, prior);
      std::vector<Vec2> disp = without_suspects(tracked, check);
      if (std::size_t(kept_count(disp)) < need || !check.clean()) continue;
      r.accepted[k] = 1;
      ++st.accepted;
      for (std::size_t i = 0; i < disp.size() && !prior.empty(); ++i)
        if (disp[i].allFinite()) miss.push_back((disp[i] - prior[i]).norm());
      fields[k] = std::move(disp);
    }
    st.miss_median_px = percentile_nearest_rank(miss, 0.5);
    st.miss_p95_px = percentile_nearest_rank(miss, 0.95);
    r.stages.push_back(st);
    std::vector<Eigen::VectorXd> x;
    std::vector<std::vector<Vec2>> y;
    for (std::size_t k = 0; k < m; ++k)
      if (r.accepted[k]) {
        x.push_back(features[k]);
        y.push_back(fields[k]);
      }
    // Too few samples for a regression (an early stage): keep the prior of the stage before.
    if (y.size() >= 2 * std::size_t(features.front().size())) r.prior = PinFieldPrior::fit(ref, x, y, o.ridge);
  }
  return r;
}

}  // namespace sb
