#include "core/loop/residual_select.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <sstream>
#include <stdexcept>

#include "core/base/format.hpp"
#include "core/base/strings.hpp"

namespace sb {

namespace {

void require_consistent(const ValidationErrors& e) {
  if (e.sq_err_px2.empty() || e.sq_err_px2.size() != e.count.size())
    throw std::invalid_argument("validation errors: need one squared-error sum and one count per sample (got " +
                                std::to_string(e.sq_err_px2.size()) + " and " + std::to_string(e.count.size()) + ")");
}

// Uniform index in [0, n) from a 64-bit draw (multiply-shift: the same on every platform, unlike
// std::uniform_int_distribution whose algorithm is implementation-defined).
std::size_t draw_index(std::mt19937_64& rng, std::size_t n) {
  return static_cast<std::size_t>((static_cast<unsigned __int128>(rng()) * n) >> 64);
}

// Linear interpolation between order statistics of a sorted vector, q in [0, 1].
double quantile_sorted(const std::vector<double>& sorted, double q) {
  const double pos = q * static_cast<double>(sorted.size() - 1);
  const auto lo = static_cast<std::size_t>(std::floor(pos));
  const std::size_t hi = std::min(lo + 1, sorted.size() - 1);
  return sorted[lo] + (pos - static_cast<double>(lo)) * (sorted[hi] - sorted[lo]);
}

double improvement_pct(double reference_rmse, double candidate_rmse) {
  return 100.0 * (reference_rmse - candidate_rmse) / reference_rmse;
}

// "creep+lens", or "(base)" for no effects.
std::string chain_label(const std::vector<std::string>& ids) { return ids.empty() ? "(base)" : join(ids, "+"); }

}  // namespace

double validation_rmse(const ValidationErrors& e) {
  require_consistent(e);
  double sse = 0.0, n = 0.0;
  for (std::size_t i = 0; i < e.sq_err_px2.size(); ++i) {
    sse += e.sq_err_px2[i];
    n += e.count[i];
  }
  if (n <= 0.0) throw std::invalid_argument("validation errors: zero residual count");
  return std::sqrt(sse / n);
}

double gaussian_bic(double sse, double n, std::size_t k) {
  if (!(n > 0.0) || !(sse >= 0.0)) throw std::invalid_argument("BIC needs n > 0 and SSE >= 0");
  // A perfect fit has no finite log-likelihood; floor the variance at a tiny value instead.
  const double variance = std::max(sse / n, 1e-300);
  return n * std::log(variance) + static_cast<double>(k) * std::log(n);
}

Interval bootstrap_improvement_pct(const ValidationErrors& reference, const ValidationErrors& candidate, int resamples,
                                   std::uint64_t seed, double confidence) {
  require_consistent(reference);
  require_consistent(candidate);
  if (reference.sq_err_px2.size() != candidate.sq_err_px2.size())
    throw std::invalid_argument("bootstrap: reference and candidate were scored on different sample counts (" +
                                std::to_string(reference.sq_err_px2.size()) + " vs " +
                                std::to_string(candidate.sq_err_px2.size()) + ")");
  if (resamples < 2 || !(confidence > 0.0 && confidence < 1.0))
    throw std::invalid_argument("bootstrap: need >= 2 resamples and a confidence in (0, 1)");
  const std::size_t n = reference.sq_err_px2.size();
  std::mt19937_64 rng(seed);
  std::vector<double> improvements;
  improvements.reserve(static_cast<std::size_t>(resamples));
  for (int b = 0; b < resamples; ++b) {
    double ref_sse = 0.0, ref_n = 0.0, cand_sse = 0.0, cand_n = 0.0;
    for (std::size_t k = 0; k < n; ++k) {
      const std::size_t i = draw_index(rng, n);  // paired: the same sample for both models
      ref_sse += reference.sq_err_px2[i];
      ref_n += reference.count[i];
      cand_sse += candidate.sq_err_px2[i];
      cand_n += candidate.count[i];
    }
    if (ref_sse <= 0.0 || ref_n <= 0.0 || cand_n <= 0.0) continue;  // improvement undefined on this draw
    improvements.push_back(improvement_pct(std::sqrt(ref_sse / ref_n), std::sqrt(cand_sse / cand_n)));
  }
  if (improvements.size() < 2) throw std::invalid_argument("bootstrap: the reference has no error to improve");
  std::sort(improvements.begin(), improvements.end());
  const double tail = 0.5 * (1.0 - confidence);
  return {quantile_sorted(improvements, tail), quantile_sorted(improvements, 1.0 - tail)};
}

double fingerprint_explained_pct(const FitResult& reference, const FitResult& candidate,
                                 const SelectionOptions& options) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  if (!(reference.held_count > 0) || !(reference.held_sse_px2 > 0)) return nan;
  if (std::sqrt(reference.held_signal_px2 / reference.held_count) < options.min_fingerprint_signal_px) return nan;
  return 100.0 * (1.0 - candidate.held_sse_px2 / reference.held_sse_px2);
}

CandidateScore score_candidate(const FitResult& reference, const FitResult& candidate,
                               const SelectionOptions& options) {
  CandidateScore s;
  s.reference_rmse_px = validation_rmse(reference.validation);
  s.rmse_px = validation_rmse(candidate.validation);
  s.improvement_pct = improvement_pct(s.reference_rmse_px, s.rmse_px);
  s.improvement_ci_pct = bootstrap_improvement_pct(reference.validation, candidate.validation,
                                                   options.bootstrap_resamples, options.seed, options.confidence);
  s.delta_bic = gaussian_bic(candidate.calibration_sse_px2, candidate.calibration_count, candidate.free_params) -
                gaussian_bic(reference.calibration_sse_px2, reference.calibration_count, reference.free_params);
  const bool interval_ok = s.improvement_ci_pct.low > options.min_lower_bound_pct;
  const bool bic_ok = s.delta_bic < 0.0;
  s.veto = candidate.veto;
  s.model_form_symptom = candidate.model_form_symptom;
  s.fingerprint_pct = fingerprint_explained_pct(reference, candidate, options);
  const bool fingerprint_ok = std::isfinite(s.fingerprint_pct) && s.fingerprint_pct >= options.min_fingerprint_pct &&
                              s.improvement_pct > 0.0;
  s.fingerprint = candidate.fingerprint;
  // An effect with a fingerprint needs it found on both splits. Found evidence that lies beyond model form
  // (the held drift) is judged where it lies: the effect, at the fingerprint's parameters, must explain the
  // validation drift (or pass the whole-field interval: a base model that is not rate-independent, TacSL,
  // predicts a drift of its own) and must not make the whole field certainly worse (the interval's upper end
  // above 0); the whole-field gain and BIC measure the base model's form there more than the effect. Other
  // evidence keeps the whole-field rule.
  const bool own_evidence = !s.fingerprint || s.fingerprint->consistent;
  const bool beyond_form = s.fingerprint && s.fingerprint->consistent && s.fingerprint->beyond_model_form;
  const bool drift_ok = std::isfinite(s.fingerprint_pct) && s.fingerprint_pct >= options.min_fingerprint_pct;
  const bool not_worse = s.improvement_ci_pct.high > 0.0;
  // The rest-grid lens: its evidence is not in the field, and the field's verdict on it is the base's form.
  const bool evidence_rule = beyond_form && s.fingerprint->acceptance == FingerprintCheck::Acceptance::kEvidence;
  if (evidence_rule)
    s.accepted = s.veto.empty();
  else if (beyond_form)
    s.accepted = (drift_ok || interval_ok) && not_worse && s.veto.empty();
  else
    s.accepted = own_evidence && (interval_ok || fingerprint_ok) && bic_ok && s.veto.empty();
  std::ostringstream why;
  why << "improvement " << format_number(s.improvement_pct, "%.1f") << " % ["
      << format_number(s.improvement_ci_pct.low, "%.1f") << ", " << format_number(s.improvement_ci_pct.high, "%.1f")
      << "], dBIC " << format_number(s.delta_bic, "%.0f");
  if (std::isfinite(s.fingerprint_pct))
    why << ", held drift explained " << format_number(s.fingerprint_pct, "%.0f") << " %";
  if (s.fingerprint)
    why << ", fingerprint " << s.fingerprint->param << " " << format_number(s.fingerprint->calibration, "%.3g") << " / "
        << format_number(s.fingerprint->validation, "%.3g") << " (calibration / validation)";
  why << ": ";
  if (s.accepted && evidence_rule)
    why << "accepted on its fingerprint (held at its evidence, which lies outside the displacement field; the "
           "whole-field change is reported, not required)";
  else if (s.accepted && beyond_form)
    why << "accepted on its fingerprint (the validation drift explained, the whole field not certainly worse)";
  else if (s.accepted)
    why << (interval_ok ? "accepted" : "accepted on the held-drift fingerprint");
  else if (!own_evidence)
    why << "fingerprint not found (" << s.fingerprint->verdict << ")";
  else if (!s.veto.empty())
    why << s.veto;
  else if (beyond_form && !drift_ok && !interval_ok)
    why << "at the fingerprint's parameters it explains less than " << options.min_fingerprint_pct
        << "% of the validation drift and the interval's lower bound is not above " << options.min_lower_bound_pct
        << "%";
  else if (beyond_form)
    why << "it makes the whole validation field certainly worse (interval below 0)";
  else if (!interval_ok)
    why << "interval lower bound not above " << options.min_lower_bound_pct << "%";
  else
    why << "calibration BIC does not improve (extra parameters not paid for)";
  s.reason = why.str();
  return s;
}

SelectionResult select_effects(const std::vector<std::string>& candidate_ids, const FitAndScore& fit_and_score,
                               const SelectionOptions& options) {
  SelectionResult result;
  result.base = fit_and_score({});
  result.base_rmse_px = validation_rmse(result.base.validation);
  FitResult current = result.base;

  std::vector<std::string> remaining = candidate_ids;
  while (result.selected.size() < options.max_effects && !remaining.empty()) {
    std::vector<CandidateScore> round;
    std::vector<FitResult> fits;
    for (const auto& c : remaining) {
      std::vector<std::string> ids = result.selected;
      ids.push_back(c);
      fits.push_back(fit_and_score(ids));
      CandidateScore s = score_candidate(current, fits.back(), options);
      s.candidate = c;
      s.effect_ids = ids;
      s.reason = chain_label(ids) + ": " + s.reason;
      round.push_back(std::move(s));
    }
    // The best accepted candidate by point improvement; ties go to the higher lower bound.
    int best = -1;
    for (std::size_t i = 0; i < round.size(); ++i) {
      if (!round[i].accepted) continue;
      if (best < 0 || round[i].improvement_pct > round[best].improvement_pct ||
          (round[i].improvement_pct == round[best].improvement_pct &&
           round[i].improvement_ci_pct.low > round[best].improvement_ci_pct.low))
        best = static_cast<int>(i);
    }
    result.rounds.push_back(round);
    if (best < 0) break;
    result.selected.push_back(round[best].candidate);
    current = fits[best];
    remaining.erase(remaining.begin() + best);
  }
  result.final_fit = current;
  result.final_rmse_px = validation_rmse(current.validation);
  return result;
}

}  // namespace sb
