#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <functional>
#include <map>

#include "core/loop/residual_select.hpp"

// This file's names in a namespace of its own: the unity build (CMAKE_UNITY_BUILD) compiles several
// test files as one translation unit.
namespace test_residual_select {

using namespace sb;

namespace {

constexpr double kExactPct = 1e-9;  // percent: closed-form ratios
constexpr std::size_t kSamples = 200;

// Deterministic pseudo-noise in [0, 1) (a fixed low-discrepancy sequence, no RNG state).
double unit_noise(std::size_t i, double phase) { return std::fmod(0.6180339887 * double(i) + phase, 1.0); }

// Base per-sample errors: squared-error sums 50..150 px^2 over 100 components each.
ValidationErrors base_errors() {
  ValidationErrors e;
  for (std::size_t i = 0; i < kSamples; ++i) {
    e.sq_err_px2.push_back(50.0 + 100.0 * unit_noise(i, 0.1));
    e.count.push_back(100.0);
  }
  return e;
}

// Every sample's squared error times factor(i).
template <class F>
ValidationErrors scaled(const ValidationErrors& e, F factor) {
  ValidationErrors s = e;
  for (std::size_t i = 0; i < s.sq_err_px2.size(); ++i) s.sq_err_px2[i] *= factor(i);
  return s;
}

FitResult fit(ValidationErrors v, double calibration_sse, std::size_t free_params) {
  FitResult f;
  f.validation = std::move(v);
  f.calibration_sse_px2 = calibration_sse;
  f.calibration_count = 10000.0;
  f.free_params = free_params;
  return f;
}

std::string key(const std::vector<std::string>& ids) {
  std::vector<std::string> s = ids;
  std::sort(s.begin(), s.end());
  std::string k;
  for (const auto& id : s) k += id + ";";
  return k;
}

// A lookup-table fit_and_score that also counts the calls.
struct TableFit {
  std::map<std::string, FitResult> table;
  int calls = 0;
  FitResult operator()(const std::vector<std::string>& ids) {
    ++calls;
    return table.at(key(ids));
  }
};

}  // namespace

TEST_CASE("bootstrap interval of a uniform improvement is that improvement", "[effects][residual_select]") {
  // Every sample's squared error times (1 - f)^2: any resample's RMSE ratio is 1 - f, so every
  // resampled improvement is exactly 100 f and so are both ends of the interval.
  const double f = 0.2;
  const ValidationErrors base = base_errors();
  const ValidationErrors cand = scaled(base, [&](std::size_t) { return (1 - f) * (1 - f); });
  const Interval ci = bootstrap_improvement_pct(base, cand, 500, 7, 0.95);
  CHECK(std::abs(ci.low - 100 * f) < kExactPct);
  CHECK(std::abs(ci.high - 100 * f) < kExactPct);
  CHECK(std::abs(validation_rmse(cand) / validation_rmse(base) - (1 - f)) < kExactPct);
  // Mismatched sample sets are an error.
  ValidationErrors shorter = cand;
  shorter.sq_err_px2.pop_back();
  shorter.count.pop_back();
  CHECK_THROWS_AS(bootstrap_improvement_pct(base, shorter, 500, 7, 0.95), std::invalid_argument);
}

TEST_CASE("bootstrap is deterministic and brackets a noisy improvement", "[effects][residual_select]") {
  const ValidationErrors base = base_errors();
  // Per-sample factors in [0.5, 0.9): a real but uneven improvement.
  const ValidationErrors cand = scaled(base, [](std::size_t i) { return 0.5 + 0.4 * unit_noise(i, 0.37); });
  const Interval a = bootstrap_improvement_pct(base, cand, 2000, 11, 0.95);
  const Interval b = bootstrap_improvement_pct(base, cand, 2000, 11, 0.95);
  CHECK(a.low == b.low);
  CHECK(a.high == b.high);
  const double point = 100 * (1 - validation_rmse(cand) / validation_rmse(base));
  CHECK(a.low < point);
  CHECK(point < a.high);
  CHECK(a.low > 0.0);
}

TEST_CASE("selection: clear improvement selected, noise-level and unpaid ones not, greedy second",
          "[effects][residual_select]") {
  const ValidationErrors base = base_errors();
  TableFit t;
  t.table[key({})] = fit(base, 1000.0, 3);
  // "creep": RMSE down 20% on every sample.
  t.table[key({"creep"})] = fit(scaled(base, [](std::size_t) { return 0.64; }), 640.0, 5);
  // "noise": per-sample factors 1 +- 2.5% averaging 1: a noise-level change.
  const auto jitter = [](std::size_t i) { return 1.0 + 0.05 * (unit_noise(i, 0.71) - 0.5); };
  t.table[key({"noise"})] = fit(scaled(base, jitter), 995.0, 4);
  // "lens": 10% better alone, and 10% better again on top of creep.
  t.table[key({"lens"})] = fit(scaled(base, [](std::size_t) { return 0.81; }), 810.0, 5);
  t.table[key({"creep", "lens"})] = fit(scaled(base, [](std::size_t) { return 0.64 * 0.81; }), 518.4, 7);
  t.table[key({"creep", "noise"})] = fit(scaled(base, [&](std::size_t i) { return 0.64 * jitter(i); }), 639.0, 6);

  const SelectionResult r = select_effects({"noise", "lens", "creep"}, std::ref(t));
  REQUIRE(r.selected == std::vector<std::string>{"creep", "lens"});
  // 1 base fit + 3 candidates + 2 second-round candidates (max_effects = 2 stops there).
  CHECK(t.calls == 6);
  REQUIRE(r.rounds.size() == 2);
  for (const auto& s : r.rounds[0]) {
    if (s.candidate == "noise") {
      CHECK(!s.accepted);
      CHECK(s.improvement_ci_pct.low < 1.0);
    }
    if (s.candidate == "creep") CHECK(std::abs(s.improvement_pct - 20.0) < kExactPct);
    if (s.candidate == "lens") CHECK(s.accepted);  // accepted but not the best
  }
  // The second round is measured against base+creep: lens improves it by another 10%.
  for (const auto& s : r.rounds[1])
    if (s.candidate == "lens") CHECK(std::abs(s.improvement_pct - 10.0) < kExactPct);
  // Squared errors times 0.64 * 0.81: RMSE times 0.8 * 0.9 = 0.72.
  CHECK(std::abs(r.final_rmse_px / r.base_rmse_px - 0.72) < kExactPct);
}

TEST_CASE("selection: nothing selected when nothing helps; BIC rejects an unpaid improvement",
          "[effects][residual_select]") {
  const ValidationErrors base = base_errors();
  TableFit t;
  t.table[key({})] = fit(base, 1000.0, 3);
  // Validation 5% better, but the calibration SSE drops by only 0.1% for 500 extra parameters:
  // dBIC = n ln(0.999) + 500 ln n = 10000 (-0.0010005) + 500 * 9.21 > 0 -> rejected.
  t.table[key({"overfit"})] = fit(scaled(base, [](std::size_t) { return 0.9025; }), 999.0, 503);
  const SelectionResult r = select_effects({"overfit"}, std::ref(t));
  CHECK(r.selected.empty());
  REQUIRE(r.rounds.size() == 1);
  CHECK(r.rounds[0][0].improvement_ci_pct.low > 1.0);
  CHECK(r.rounds[0][0].delta_bic > 0.0);
  CHECK(!r.rounds[0][0].accepted);
  CHECK(r.final_rmse_px == r.base_rmse_px);
}

TEST_CASE("selection: a vetoed fit (parameter at a bound) is not accepted whatever its gain",
          "[effects][residual_select]") {
  const ValidationErrors base = base_errors();
  FitResult ref = fit(base, 1000.0, 3);
  // 10 % better everywhere (RMSE factor sqrt(0.81) = 0.9), calibration SSE halved: passes interval and BIC ...
  FitResult cand = fit(scaled(base, [](std::size_t) { return 0.81; }), 500.0, 5);
  const SelectionOptions o;
  CHECK(score_candidate(ref, cand, o).accepted);
  // ... until the caller vetoes it.
  cand.veto = "model-form symptom: x.beta = 2000 at a bound of its physical range";
  cand.model_form_symptom = true;
  const CandidateScore s = score_candidate(ref, cand, o);
  CHECK(!s.accepted);
  CHECK(s.model_form_symptom);
  CHECK(s.reason.find("model-form symptom") != std::string::npos);
}

TEST_CASE("selection: the held-drift fingerprint accepts a small gain, only when the drift is above noise",
          "[effects][residual_select]") {
  const ValidationErrors base = base_errors();
  const SelectionOptions o;  // fingerprint: >= 50 % explained of a drift with RMS >= 0.15 px
  FitResult ref = fit(base, 1000.0, 3);
  // A 0.5 % squared-error gain: RMSE improvement 100 (1 - sqrt(0.995)) = 0.25 %, under the 1 % margin.
  FitResult cand = fit(scaled(base, [](std::size_t) { return 0.995; }), 990.0, 5);
  CHECK(!score_candidate(ref, cand, o).accepted);
  // Drift RMS sqrt(0.09) = 0.3 px over 100 marker-frames, all of it unexplained by the reference;
  // the candidate leaves a quarter: 75 % explained >= 50 %.
  ref.held_count = cand.held_count = 100;
  ref.held_signal_px2 = cand.held_signal_px2 = 9.0;
  ref.held_sse_px2 = 9.0;
  cand.held_sse_px2 = 2.25;
  CHECK(fingerprint_explained_pct(ref, cand, o) == Approx(75.0));
  CHECK(score_candidate(ref, cand, o).accepted);
  // The same ratio on a drift of RMS sqrt(0.01) = 0.1 px (tracker noise level) is no evidence.
  ref.held_signal_px2 = cand.held_signal_px2 = 1.0;
  CHECK(std::isnan(fingerprint_explained_pct(ref, cand, o)));
  CHECK(!score_candidate(ref, cand, o).accepted);
}

TEST_CASE("selection: evidence beyond model form, the held-drift rule (creep) and the evidence rule (rest-grid lens)",
          "[effects][residual_select]") {
  const ValidationErrors base = base_errors();
  const SelectionOptions o;
  const FitResult ref = fit(base, 1000.0, 3);
  // 0.5 % less squared error on every sample: a 0.25 % RMSE gain whose interval is [0.25, 0.25] %, under the
  // 1 % margin; BIC worse (calibration SSE unchanged, 2 more parameters).
  FitResult cand = fit(scaled(base, [](std::size_t) { return 0.995; }), 1000.0, 5);
  FingerprintCheck f;
  f.consistent = true;
  f.beyond_model_form = true;
  cand.fingerprint = f;
  // Creep's rule: no drift in the data and the interval under the margin: not accepted.
  CHECK_FALSE(score_candidate(ref, cand, o).accepted);
  // The rest-grid lens: the evidence is not in the field; accepted on it ...
  cand.fingerprint->acceptance = FingerprintCheck::Acceptance::kEvidence;
  const CandidateScore s = score_candidate(ref, cand, o);
  CHECK(s.accepted);
  CHECK(s.improvement_pct == Approx(100.0 * (1.0 - std::sqrt(0.995))));
  CHECK(s.reason.find("accepted on its fingerprint (held at its evidence") != std::string::npos);
  // ... also when the whole field is certainly worse (the base's form leaning on the lens; reported) ...
  FitResult worse = cand;
  worse.validation = scaled(base, [](std::size_t) { return 1.05; });
  const CandidateScore w = score_candidate(ref, worse, o);
  CHECK(w.improvement_ci_pct.high < 0.0);
  CHECK(w.accepted);
  // ... never with a veto, nor when the fingerprint was not found.
  FitResult vetoed = cand;
  vetoed.veto = "model-form symptom: x at a bound";
  CHECK_FALSE(score_candidate(ref, vetoed, o).accepted);
  FitResult missing = cand;
  missing.fingerprint->consistent = false;
  missing.fingerprint->verdict = "rest grid: a lattice with k1 0.001 +- 0.0003: not found, k1 is none";
  const CandidateScore m = score_candidate(ref, missing, o);
  CHECK_FALSE(m.accepted);
  CHECK(m.reason.find("fingerprint not found (rest grid") != std::string::npos);
}

}  // namespace test_residual_select
