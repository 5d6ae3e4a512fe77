// The fit engine (fit.hpp for the objective): stages run one after the other, each a coarse scan and the bounded
// Levenberg-Marquardt minimiser over the model's runs, with progress and cancel. What a model's stages are is the
// policy in fit.cpp.
#include "core/base/reproducible.hpp"
#include "core/calibration/fit.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>

#include "core/base/elapsed.hpp"
#include "core/base/strings.hpp"
#include "core/calibration/bounded_lm.hpp"
#include "core/effects/effects.hpp"
#include "core/models/model_family.hpp"

namespace sb {

namespace {

// Finite-difference half-steps in the optimiser's coordinates: 1e-3 in log space is a 0.1 % change of
// the value. Deliberately coarse so the difference steps over the models' small non-smooth features
// (stick/slip switches of single points, FOTS's integer-pixel truncation) instead of reading zero.
constexpr double kDiffStepLog = 1e-3;
constexpr double kDiffStepLinear = 1e-3;  // relative to max(|x|, 1 % of the range)
// The most a parameter moves in one step: a decade (log-scale parameters) or a quarter of its range.
const double kMaxStepLog = std::log(10.0);
constexpr double kMaxStepLinear = 0.25;
// Coarse scan: default * 10^(k * step) for k = -n..n, i.e. two decades either side of the default.
constexpr double kScanDecades = 2.0;
constexpr int kScanPoints1d = 9;
constexpr int kScanPoints2d = 5;
// Below this <pred, pred> a rescale stage keeps s = 1 (the model predicts nothing to scale).
constexpr double kRescaleMinNorm2 = 1e-12;

// A model with a single-precision switch (its family's descriptor names it: hydroshear-contact's "float32") runs in
// double while fitted: its float sums move by ~1e-7 of the field, noise far above the solver's parameter tolerance
// (1e-10), and on twin_punch the fit stopped early in that noise (0.393 px validation against 0.335 in double).
// A model id that is no family's form (a test's own model) has none.
std::string single_precision_switch(const std::string& model_id) {
  const ModelFamily* family = find_model_family_of_form(model_id.substr(0, model_id.find('+')));
  return family != nullptr ? family->single_precision_switch : std::string();
}

void in_double(const std::string& precision_switch, ParamSet* p) {
  if (!precision_switch.empty() && p->index_of(precision_switch) >= 0) p->set(precision_switch, 0);
}

// The stage's parameters in optimiser coordinates x (log(value) for log_scale specs) with bounds.
struct ParamMap {
  std::vector<int> index;
  std::vector<bool> log;
  std::vector<bool> field_only;  // the model's own table says so (its finite differences replay less)
  // An effect's parameter on the base's field (EffectModel::acts_after_base): its finite differences replay the
  // base's remembered field (EffectModel::remember_base_field), so they run first after the central run.
  std::vector<bool> after_base;
  std::vector<double> lo, hi;
  std::string precision_switch;  // set to 0 in every run (in_double)

  ParamMap(const ParamSet& p, const std::vector<std::string>& names, const std::string& model_id)
      : precision_switch(single_precision_switch(model_id)) {
    for (const auto& n : names) {
      const int i = p.index_of(n);
      if (i < 0) throw std::invalid_argument("fit: model '" + model_id + "' has no parameter '" + n + "'");
      const ParamSpec& s = p.specs()[i];
      if (s.is_switch) throw std::invalid_argument("fit: '" + n + "' of model '" + model_id + "' is a switch (0 or 1)");
      const bool lg = s.log_scale && s.min > 0;
      index.push_back(i);
      log.push_back(lg);
      field_only.push_back(false);
      after_base.push_back(false);
      lo.push_back(lg ? std::log(s.min) : s.min);
      hi.push_back(lg ? std::log(s.max) : s.max);
    }
  }
  int size() const { return static_cast<int>(index.size()); }
  // Marks the parameters the model (as built: an effect with state clears them all) calls field-only.
  void mark_field_only(const ParamSet& model_table, const ParamSet& p) {
    for (int k = 0; k < size(); ++k) {
      const int j = model_table.index_of(p.specs()[index[k]].name);
      field_only[k] = j >= 0 && model_table.specs()[j].field_only;
    }
  }
  void mark_after_base(const ShearModel& model, const ParamSet& p) {
    const auto* effect_model = dynamic_cast<const EffectModel*>(&model);
    for (int k = 0; k < size(); ++k)
      after_base[k] = effect_model != nullptr && effect_model->acts_after_base(p.specs()[index[k]].name);
  }
  // The finite differences' order: the parameters after the base first (the memo holds the central run's
  // base field until a column that changes it), then the others as listed.
  std::vector<int> column_order() const {
    std::vector<int> order;
    for (int k = 0; k < size(); ++k)
      if (after_base[k]) order.push_back(k);
    for (int k = 0; k < size(); ++k)
      if (!after_base[k]) order.push_back(k);
    return order;
  }
  double to_x(int k, double value) const { return log[k] ? std::log(value) : value; }
  std::vector<double> to_x(const ParamSet& p) const {
    std::vector<double> x(index.size());
    for (int k = 0; k < size(); ++k) x[k] = std::clamp(to_x(k, p[index[k]]), lo[k], hi[k]);
    return x;
  }
  void apply(const double* x, ParamSet* p) const {
    for (int k = 0; k < size(); ++k) {
      const ParamSpec& s = p->specs()[index[k]];
      const double v = log[k] ? std::exp(x[k]) : x[k];
      p->set(static_cast<std::size_t>(index[k]), std::clamp(v, s.min, s.max));
    }
  }
};

// sqrt(rho(q) / q) for a squared error q: scaling the 2-vector error by it makes its squared norm rho(q).
double robust_factor(RobustLoss loss, double a, double q) {
  if (loss == RobustLoss::kNone || q <= 0) return 1.0;
  const double a2 = a * a;
  double rho = q;
  if (loss == RobustLoss::kHuber) rho = q <= a2 ? q : 2 * a * std::sqrt(q) - a2;
  if (loss == RobustLoss::kCauchy) rho = a2 * std::log1p(q / a2);
  return std::sqrt(rho / q);
}

struct SampleSlot {
  const FitSample* sample;
  ShearModel* model;
  const std::vector<int>* active;
  int offset;  // first scored marker-frame of this sample
};

// A Central run keeps each sample's model state at its first scored frame, for the columns of field-only parameters
// to start from (kFromScored), for at most this many samples; the others' columns run the whole path (the same
// values, slower). A state is O(contact): on the TacTip 0.4 MB, so a fit of 5005 samples kept 2 GB of them. The
// loop's search (ResidualOptions::search_set) fits at most 2000 samples and keeps every one.
constexpr int kMaxScoredStarts = 2000;

// Runs the model over the stage's samples for a parameter vector and forms the residual vector.
class StageEvaluator {
 public:
  StageEvaluator(std::vector<SampleSlot> slots, const ParamSet& base, const ParamMap& map, bool rescale,
                 RobustLoss robust, double robust_scale, const std::atomic<bool>* cancel)
      : slots_(std::move(slots)),
        base_(base),
        map_(map),
        rescale_(rescale),
        robust_(robust),
        robust_scale_(robust_scale),
        cancel_(cancel) {
    // The memo only pays where a column replays it: elsewhere it would copy every run's field for nothing.
    const bool replayed = std::find(map.after_base.begin(), map.after_base.end(), true) != map.after_base.end();
    for (const auto& s : slots_) {
      n_ += static_cast<int>(s.active->size());
      if (auto* effect_model = dynamic_cast<EffectModel*>(s.model)) effect_model->remember_base_field(replayed);
    }
    pred_.resize(n_);
    meas_.resize(n_);
    for (const auto& s : slots_) {
      const int m = static_cast<int>(s.sample->meas_px.front().size());
      for (std::size_t a = 0; a < s.active->size(); ++a) {
        const int f = (*s.active)[a];
        meas_[s.offset + a] = s.sample->meas_px[f / m][f % m];
      }
    }
  }
  int marker_frames() const { return n_; }
  int evaluations() const { return evaluations_; }
  bool cancelled() const { return cancel_ && cancel_->load(); }

  // How a run starts: from reset, keeping a copy of each model just before its first scored frame (Central),
  // or not (Full); or from that copy (FromScored: only a field-only parameter differs from the Central run).
  enum class Run { kCentral, kFull, kFromScored };

  // Residuals (2 per scored marker-frame) at x; false when cancelled. sse: raw sum |s pred - meas|^2.
  bool residuals(const double* x, double* r, double* scale_out = nullptr, double* sse_out = nullptr,
                 Run run = Run::kFull) {
    if (cancelled()) return false;
    ParamSet p = base_;
    map_.apply(x, &p);
    in_double(map_.precision_switch, &p);
    if (run == Run::kCentral) scored_start_.resize(slots_.size());
    std::atomic<bool> stop{false};
    tbb::parallel_for(0, static_cast<int>(slots_.size()), [&](int i) {
      if (cancelled()) {
        stop = true;
        return;
      }
      const SampleSlot& s = slots_[i];
      const int m = static_cast<int>(s.sample->meas_px.front().size());
      const std::size_t first_scored = static_cast<std::size_t>(s.active->front() / m);
      std::vector<std::vector<Vec2>> pred(s.sample->X_EI.size());
      if (run == Run::kFromScored && static_cast<std::size_t>(i) < scored_start_.size() && scored_start_[i]) {
        auto model = scored_start_[i]->clone();
        model->set_params(p);
        simulate_frames(*model, *s.sample, first_scored, &pred);
      } else {
        s.model->set_params(p);
        s.model->reset();
        const auto keep = [&](std::size_t k) {
          if (run == Run::kCentral && k == first_scored && i < kMaxScoredStarts) scored_start_[i] = s.model->clone();
        };
        simulate_frames(*s.model, *s.sample, 0, &pred, keep);
      }
      for (std::size_t a = 0; a < s.active->size(); ++a) {
        const int f = (*s.active)[a];
        pred_[s.offset + a] = pred[f / m][f % m];
      }
    });
    ++evaluations_;
    if (stop || cancelled()) return false;
    const double s = rescale_ ? best_scale() : 1.0;
    double sse = 0;
    for (int i = 0; i < n_; ++i) {
      const Vec2 e = s * pred_[i] - meas_[i];
      const double q = e.squaredNorm();
      sse += q;
      const Vec2 re = e * robust_factor(robust_, robust_scale_, q);
      const std::ptrdiff_t k = 2 * static_cast<std::ptrdiff_t>(i);
      r[k] = re.x();
      r[k + 1] = re.y();
    }
    if (scale_out) *scale_out = s;
    if (sse_out) *sse_out = sse;
    return true;
  }
  // 1/2 sum r^2 (the least-squares cost), or +inf when cancelled.
  double cost(const double* x, double* scale_out = nullptr, double* sse_out = nullptr) {
    std::vector<double> r(2 * static_cast<std::size_t>(n_));
    if (!residuals(x, r.data(), scale_out, sse_out)) return std::numeric_limits<double>::infinity();
    double c = 0;
    for (double v : r) c += v * v;
    return 0.5 * c;
  }

 private:
  // argmin_s sum |s pred - meas|^2 = <pred, meas> / <pred, pred>, kept >= 0 so the shape is not mirrored.
  double best_scale() const {
    double pm = 0, pp = 0;
    for (int i = 0; i < n_; ++i) {
      pm += pred_[i].dot(meas_[i]);
      pp += pred_[i].squaredNorm();
    }
    return pp > kRescaleMinNorm2 ? std::max(pm / pp, 0.0) : 1.0;
  }

  std::vector<SampleSlot> slots_;
  // Aliased: the base parameters, the map and the cancel flag belong to the fit that runs this evaluator
  // (run_stage) and outlive it.
  const ParamSet& base_;
  const ParamMap& map_;
  bool rescale_;
  RobustLoss robust_;
  double robust_scale_;
  const std::atomic<bool>* cancel_;
  int n_ = 0;
  int evaluations_ = 0;
  std::vector<Vec2> pred_, meas_;
  std::vector<std::unique_ptr<ShearModel>> scored_start_;  // per slot, the last Central run's state
};

// One-sided differences from the central run, toward the inside of the bounds: one model run per column. Central
// differences cost two; the Jacobian is what a stage pays for (hydroshear-contact's joint stage: 13 columns, one
// Jacobian per accepted step), and the step h stays as coarse, so it still steps over the models' small non-smooth
// features. docs/performance.md, "Fits: one run per Jacobian column".
class StageCost {
 public:
  StageCost(StageEvaluator* ev, const ParamMap* map) : ev_(ev), map_(map) {}
  int num_residuals() const { return 2 * ev_->marker_frames(); }

  // The residuals at x from a Central run: its state before the scored frames is what the columns of a
  // field-only parameter start from. False when cancelled.
  bool residuals(const std::vector<double>& x, std::vector<double>* r) {
    last_x_.clear();
    if (!ev_->residuals(x.data(), r->data(), nullptr, nullptr, StageEvaluator::Run::kCentral)) return false;
    last_x_ = x;
    return true;
  }
  // J(x) row-major, from the residuals r of the Central run at x (rerun if the last run was elsewhere).
  bool jacobian(const std::vector<double>& x, const std::vector<double>& r, std::vector<double>* J) {
    if (x != last_x_) {
      std::vector<double> again(r.size());
      if (!residuals(x, &again)) return false;
    }
    const int P = map_->size();
    const int n = num_residuals();
    J->assign(static_cast<std::size_t>(n) * P, 0.0);
    std::vector<double> xs = x, rs(static_cast<std::size_t>(n));
    for (const int k : map_->column_order()) {
      const double h = map_->log[k] ? kDiffStepLog
                                    : kDiffStepLinear * std::max(std::abs(x[k]), 0.01 * (map_->hi[k] - map_->lo[k]));
      // Forward, or backward where the forward step would leave the bounds (HydroShear's mu sits at its upper
      // bound on the TacTip); zero where the range is narrower than the step.
      xs[k] = x[k] + h <= map_->hi[k] ? x[k] + h : std::max(x[k] - h, map_->lo[k]);
      const auto run = map_->field_only[k] && !map_->after_base[k] ? StageEvaluator::Run::kFromScored
                                                                   : StageEvaluator::Run::kFull;
      const double dx = xs[k] - x[k];
      if (dx != 0 && !ev_->residuals(xs.data(), rs.data(), nullptr, nullptr, run)) return false;
      if (dx != 0)
        for (int i = 0; i < n; ++i) (*J)[static_cast<std::size_t>(i) * P + k] = (rs[i] - r[i]) / dx;
      xs[k] = x[k];
    }
    return true;
  }

 private:
  StageEvaluator* ev_;  // aliased with the map: both belong to the stage being minimised and outlive this problem
  const ParamMap* map_;
  std::vector<double> last_x_;  // the last Central run's point
};

// The stage's least-squares problem for the minimiser, with progress and cancel.
BoundedLmResult minimize_stage(StageCost* cost, const ParamMap& map, const std::vector<double>& x,
                               const std::string& stage, const FitOptions& o) {
  BoundedLmProblem pr;
  pr.lo = map.lo;
  pr.hi = map.hi;
  pr.num_residuals = cost->num_residuals();
  for (int k = 0; k < map.size(); ++k)
    pr.max_step.push_back(map.log[k] ? kMaxStepLog : kMaxStepLinear * (map.hi[k] - map.lo[k]));
  pr.residuals = [cost](const std::vector<double>& at, std::vector<double>* r) { return cost->residuals(at, r); };
  pr.jacobian = [cost](const std::vector<double>& at, const std::vector<double>& r, std::vector<double>* J) {
    return cost->jacobian(at, r, J);
  };
  BoundedLmOptions lo;
  lo.max_iterations = o.max_iterations;
  // FitOptions' default 1e-6 of the cost (the RMSE by half of it): 1e-10 had every stage run its iteration cap,
  // e.g. friction on the TacTip five iterations at the same cost to six digits.
  lo.function_tolerance = o.function_tolerance;
  lo.on_iteration = [&](int iteration, double c) {
    if (o.progress) o.progress({stage, iteration, c});
    return !(o.cancel && o.cancel->load());
  };
  return minimize_bounded_lm(pr, x, lo);
}

// Data-independent scan points: two decades either side of the spec default (linear specs with a zero
// default: evenly over the range), clamped to the bounds.
std::vector<double> scan_axis(const ParamSpec& spec, const ParamMap& map, int k, int points) {
  std::vector<double> xs;
  for (int i = 0; i < points; ++i) {
    const double t = points == 1 ? 0.0 : -1.0 + 2.0 * i / (points - 1);
    double v = spec.default_value == 0 ? spec.min + (spec.max - spec.min) * (t + 1) / 2
                                       : spec.default_value * std::pow(10.0, kScanDecades * t);
    v = std::clamp(v, spec.min, spec.max);
    xs.push_back(std::clamp(map.to_x(k, v), map.lo[k], map.hi[k]));
  }
  return xs;
}

// Returns the best of {x0} and the scan grid (1-D and 2-D stages only). Ties keep the earlier point.
std::vector<double> coarse_scan(StageEvaluator& ev, const ParamSet& p, const ParamMap& map, std::vector<double> x0) {
  const int P = map.size();
  if (P > 2) return x0;
  const int points = P == 1 ? kScanPoints1d : kScanPoints2d;
  std::vector<std::vector<double>> axes;
  axes.reserve(P);
  for (int k = 0; k < P; ++k) axes.push_back(scan_axis(p.specs()[map.index[k]], map, k, points));
  double best = ev.cost(x0.data());
  std::vector<double> best_x = x0;
  std::vector<double> x(P);
  const int total = P == 1 ? points : points * points;
  for (int g = 0; g < total && !ev.cancelled(); ++g) {
    x[0] = axes[0][g % points];
    if (P == 2) x[1] = axes[1][g / points];
    const double c = ev.cost(x.data());
    if (c < best) {
      best = c;
      best_x = x;
    }
  }
  return best_x;
}

std::vector<const FitSample*> samples_with(const std::vector<FitSample>& all, const std::vector<std::string>& motions) {
  std::vector<const FitSample*> out;
  for (const auto& s : all)
    if (std::find(motions.begin(), motions.end(), s.motion) != motions.end()) out.push_back(&s);
  return out;
}

}  // namespace

std::vector<int> active_marker_frames(const std::vector<std::vector<Vec2>>& meas_px) {
  std::vector<int> out;
  for (std::size_t f = 0; f < meas_px.size(); ++f) {
    const auto& row = meas_px[f];
    bool active = false;
    for (const auto& d : row) active = active || (d.allFinite() && d.norm() >= kActiveFramePx);
    if (!active) continue;
    for (std::size_t j = 0; j < row.size(); ++j)
      if (row[j].allFinite()) out.push_back(static_cast<int>(f * row.size() + j));
  }
  return out;
}

RobustLoss parse_robust_loss(const std::string& name) {
  if (name == "none" || name.empty()) return RobustLoss::kNone;
  if (name == "huber") return RobustLoss::kHuber;
  if (name == "cauchy") return RobustLoss::kCauchy;
  throw std::invalid_argument("unknown robust loss '" + name + "' (none, huber, cauchy)");
}

std::string to_string(RobustLoss loss) {
  return loss == RobustLoss::kHuber ? "huber" : loss == RobustLoss::kCauchy ? "cauchy" : "none";
}

void require_calibration_split(const std::vector<FitSample>& samples) {
  for (const auto& s : samples)
    if (s.split != "calibration")
      throw std::invalid_argument("fit: sample '" + s.id + "' is from the '" + s.split +
                                  "' split; a fit may only read the calibration split");
}

bool frame_unmeasured(const FitSample& sample, std::size_t k) {
  return k < sample.meas_px.size() && nothing_tracked(sample.meas_px[k]);
}

std::vector<std::vector<Vec2>> simulate_sample(ShearModel& model, const FitSample& sample) {
  model.reset();
  std::vector<std::vector<Vec2>> out(sample.X_EI.size());
  simulate_frames(model, sample, 0, &out);
  return out;
}

void simulate_frames(ShearModel& model, const FitSample& sample, std::size_t first, std::vector<std::vector<Vec2>>* out,
                     const std::function<void(std::size_t)>& before_frame) {
  FieldOutput field;
  for (std::size_t k = first; k < sample.X_EI.size(); ++k) {
    if (before_frame) before_frame(k);
    std::vector<std::vector<Vec2>>& pred = *out;
    const double dt = k == 0 ? 0.0 : sample.dt_s;
    if (frame_unmeasured(sample, k)) {  // nothing to compare: the state only (the TacTip's slide frames)
      model.step(sample.X_EI[k], dt, nullptr);
      pred[k].assign(sample.meas_px[k].size(), Vec2::Constant(std::numeric_limits<double>::quiet_NaN()));
      continue;
    }
    model.step(sample.X_EI[k], dt, &field);
    pred[k] = field.disp_px;
  }
}

nlohmann::json CalibrationResult::report_json() const {
  nlohmann::json st = nlohmann::json::array();
  for (const auto& s : stages) {
    nlohmann::json j = {{"name", s.name},
                        {"params", s.params},
                        {"motions", s.motions},
                        {"samples", s.samples},
                        {"marker_frames", s.residuals},
                        {"loss_before", s.loss_before},
                        {"loss_after", s.loss_after},
                        {"rmse_before_px", s.rmse_before_px},
                        {"rmse_after_px", s.rmse_after_px},
                        {"iterations", s.iterations},
                        {"model_runs", s.evaluations},
                        {"termination", s.termination},
                        {"skipped", s.skipped}};
    if (timings_in_outputs()) j["time_s"] = s.time_s;
    if (s.scale != 1.0) j["rescale"] = s.scale;
    if (!s.note.empty()) j["note"] = s.note;
    st.push_back(j);
  }
  nlohmann::json out = {{"model", model_id}, {"cancelled", cancelled}, {"stages", st}};
  if (timings_in_outputs()) out["time_s"] = time_s;
  return out;
}

CalibrationResult run_fit_stages(const std::string& model_id, const FitModelFactory& make,
                                 const std::vector<FitStage>& stages, const std::vector<FitSample>& samples,
                                 const ParamSet& start, const FitOptions& o) {
  // One model per sample, cloned from one prototype per indenter (building one can be costly).
  std::map<const Indenter*, std::unique_ptr<ShearModel>> prototypes;
  const FitSampleModelFactory per_sample = [&](const FitSample& s, std::size_t) {
    auto& proto = prototypes[s.indenter.get()];
    if (!proto) proto = make(s.indenter);
    return proto->clone();
  };
  return run_fit_stages_per_sample(model_id, per_sample, stages, samples, start, o);
}

CalibrationResult run_fit_stages_per_sample(const std::string& model_id, const FitSampleModelFactory& make,
                                            const std::vector<FitStage>& stages, const std::vector<FitSample>& samples,
                                            const ParamSet& start, const FitOptions& o) {
  require_calibration_split(samples);
  const auto t_fit = std::chrono::steady_clock::now();
  CalibrationResult result{model_id, start, {}, false, 0};

  // One model per sample; scored sets fixed by the data.
  std::vector<std::unique_ptr<ShearModel>> models;
  std::vector<std::vector<int>> active;
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const FitSample& s = samples[i];
    if (s.meas_px.size() != s.X_EI.size() || s.meas_px.empty())
      throw std::invalid_argument("fit: sample '" + s.id + "' has no frames or mismatched poses/markers");
    models.push_back(make(s, i));
    active.push_back(active_marker_frames(s.meas_px));
  }

  for (const FitStage& stage : stages) {
    if (o.cancel && o.cancel->load()) {
      result.cancelled = true;
      break;
    }
    const auto t0 = std::chrono::steady_clock::now();
    StageReport rep;
    rep.name = stage.name;
    rep.params = stage.params;
    rep.motions = stage.motions;
    auto chosen = samples_with(samples, stage.motions);
    if (chosen.empty() && !stage.fallback_motions.empty()) {
      chosen = samples_with(samples, stage.fallback_motions);
      rep.note = "no " + join(stage.motions, "/") + " samples: fitted on " + join(stage.fallback_motions, "/");
      rep.motions = stage.fallback_motions;
    }
    std::vector<SampleSlot> slots;
    int offset = 0;
    for (const FitSample* s : chosen) {
      const std::size_t i = static_cast<std::size_t>(s - samples.data());
      if (active[i].empty()) continue;
      slots.push_back({s, models[i].get(), &active[i], offset});
      offset += static_cast<int>(active[i].size());
    }
    rep.samples = static_cast<int>(slots.size());
    rep.residuals = offset;
    if (slots.empty()) {
      rep.skipped = true;
      rep.note = "no calibration samples with motion " + join(rep.motions, "/") + " and a marker moving >= 0.5 px";
      rep.time_s = seconds_since(t0);
      result.stages.push_back(rep);
      continue;
    }

    ParamMap map(result.params, stage.params, model_id);
    map.mark_field_only(slots.front().model->params(), result.params);
    map.mark_after_base(*slots.front().model, result.params);
    StageEvaluator ev(std::move(slots), result.params, map, stage.rescale, o.robust, o.robust_scale_px, o.cancel);
    std::vector<double> x = map.to_x(result.params);
    double sse = 0;
    rep.loss_before = ev.cost(x.data(), nullptr, &sse);
    rep.rmse_before_px = std::sqrt(sse / rep.residuals);
    if (o.coarse_scan) x = coarse_scan(ev, result.params, map, x);

    StageCost stage_cost(&ev, &map);
    const BoundedLmResult lm = minimize_stage(&stage_cost, map, x, stage.name, o);
    if (ev.cancelled() || lm.termination == LmTermination::kAborted) {  // discard the partial stage
      result.cancelled = true;
      break;
    }
    x = lm.x;
    map.apply(x.data(), &result.params);
    rep.loss_after = ev.cost(x.data(), &rep.scale, &sse);
    rep.rmse_after_px = std::sqrt(sse / rep.residuals);
    rep.iterations = lm.iterations;
    rep.evaluations = ev.evaluations();
    rep.termination = to_string(lm.termination);
    rep.time_s = seconds_since(t0);
    result.stages.push_back(rep);
    result.time_s = seconds_since(t_fit);
    if (o.on_stage_done) o.on_stage_done(result);
  }
  result.time_s = seconds_since(t_fit);
  return result;
}

}  // namespace sb
