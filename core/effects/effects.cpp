#include "core/effects/effects.hpp"

#include "core/effects/penetration_cache.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <stdexcept>

#include "core/base/closest_name.hpp"
#include "core/base/strings.hpp"
#include "core/effects/effect_catalogue.hpp"

namespace sb {

// ---------------------------------------------------------------------------------------- Effect

void Effect::set_params(const ParamSet& params) {
  if (params.size() != params_.size())
    throw std::invalid_argument("effect '" + id() + "': expected " + std::to_string(params_.size()) +
                                " parameters, got " + std::to_string(params.size()));
  ParamSet next = params_;
  for (std::size_t i = 0; i < params.size(); ++i) {
    const std::string& name = params.specs()[i].name;
    if (next.index_of(name) < 0) throw std::invalid_argument("effect '" + id() + "' has no parameter '" + name + "'");
    next.set(name, params[i]);
  }
  params_ = std::move(next);
  params_changed();
}

namespace effects {
void require_marker_count(const EffectContext& ctx, const std::vector<Vec2>& disp_px, const char* effect_id) {
  if (ctx.sensor == nullptr) throw std::invalid_argument(std::string(effect_id) + ": no sensor in the context");
  if (disp_px.size() != ctx.sensor->markers_rest_px.size() || disp_px.size() != ctx.sensor->p_EM.size())
    throw std::invalid_argument(std::string(effect_id) + ": field has " + std::to_string(disp_px.size()) +
                                " markers, the sensor " + std::to_string(ctx.sensor->markers_rest_px.size()));
}

// Central differences of the distance, not value_and_gradient: on the surface itself an analytic SDF's nearest
// point is the point, and the direction of a zero-length difference is rounding noise (the spherical cap's).
Vec3 gel_normal_at(const Sdf& gel_sdf_E, const Vec3& p_E) {
  constexpr double h = 1e-5;  // m: well inside the smallest feature of a gel (a 0.1 mm grid cell), above rounding
  Vec3 g;
  for (int i = 0; i < 3; ++i) {
    const Vec3 dp = h * Vec3::Unit(i);
    g[i] = gel_sdf_E.value(p_E + dp) - gel_sdf_E.value(p_E - dp);
  }
  return g.squaredNorm() == 0.0 ? Vec3::Zero() : Vec3(g.normalized());
}

std::vector<double> marker_penetration(const EffectContext& ctx) {
  const std::vector<Vec3>& p_EM = ctx.sensor->p_EM;
  const Pose X_IE = ctx.X_EI.inverse(Eigen::Isometry);
  std::vector<Vec3> p_IM(p_EM.size());
  for (std::size_t k = 0; k < p_EM.size(); ++k) p_IM[k] = X_IE * p_EM[k];
  std::vector<double> depth_m(p_EM.size());
  ctx.indenter->sdf->values(p_IM, depth_m);  // one batched query (the TacTip: 327 pins per scored frame)
  for (double& h : depth_m) h = std::max(0.0, -h);
  return depth_m;
}
}  // namespace effects

// ---------------------------------------------------------------------------------------- depth

Penetration indenter_penetration(const Sdf& gel_sdf_E, const Indenter& indenter, const Pose& X_EI) {
  if (indenter.samples.p_IS.empty() && indenter.mesh.vertices.empty())
    throw std::invalid_argument("indenter '" + indenter.name + "' has no surface samples or vertices");
  // The gel lies in z <= 0 (tsd/1: its surface apex is at z = 0), so only points at or below z = 0 can
  // be inside it; the SDF is evaluated for those only (most of the indenter is above the gel).
  std::vector<Vec3> p_E;
  Vec3 lowest_E(0.0, 0.0, std::numeric_limits<double>::infinity());
  const auto consider = [&](const Vec3& p_I) {
    const Vec3 p = X_EI * p_I;
    if (p.z() < lowest_E.z()) lowest_E = p;
    if (p.z() <= 0.0) p_E.push_back(p);
  };
  for (const Vec3& p_IS : indenter.samples.p_IS) consider(p_IS);
  for (const Vec3& p_IV : indenter.mesh.vertices) consider(p_IV);
  std::vector<double> phi(p_E.size());
  if (!p_E.empty()) gel_sdf_E.values(p_E, phi);

  Penetration result;
  double weight_sum = 0.0;
  Vec2 weighted_xy = Vec2::Zero();
  for (std::size_t i = 0; i < p_E.size(); ++i) {
    const double depth = -phi[i];
    if (depth <= 0.0) continue;
    result.depth_m = std::max(result.depth_m, depth);
    weight_sum += depth;
    weighted_xy += depth * p_E[i].head<2>();
  }
  result.penetrating = result.depth_m > 0.0;
  result.centre_E = result.penetrating ? Vec2(weighted_xy / weight_sum) : Vec2(lowest_E.head<2>());
  for (std::size_t i = 0; i < p_E.size(); ++i)
    if (phi[i] < 0.0) result.radius_m = std::max(result.radius_m, (p_E[i].head<2>() - result.centre_E).norm());
  return result;
}

// ---------------------------------------------------------------------------------------- EffectModel

EffectModel::EffectModel(std::unique_ptr<ShearModel> base, std::vector<std::unique_ptr<Effect>> effects,
                         std::shared_ptr<const Sensor> sensor, std::shared_ptr<const Indenter> indenter)
    : base_(std::move(base)), effects_(std::move(effects)), sensor_(std::move(sensor)), indenter_(std::move(indenter)) {
  if (!base_) throw std::invalid_argument("EffectModel: null base model");
  if (!sensor_ || !sensor_->gel_sdf) throw std::invalid_argument("EffectModel: a sensor with a gel SDF is required");
  if (!indenter_) throw std::invalid_argument("EffectModel: null indenter");
  for (std::size_t i = 0; i < effects_.size(); ++i) {
    if (!effects_[i]) throw std::invalid_argument("EffectModel: null effect");
    for (std::size_t j = 0; j < i; ++j)
      if (effects_[j]->id() == effects_[i]->id())
        throw std::invalid_argument("EffectModel: effect '" + effects_[i]->id() + "' given twice");
  }
  rebuild_param_table();
}

std::string EffectModel::id() const {
  std::string s = base_->id();
  for (const auto& e : effects_) s += "+" + e->id();
  return s;
}

std::vector<std::string> EffectModel::effect_ids() const {
  std::vector<std::string> ids;
  for (const auto& e : effects_) ids.push_back(e->id());
  return ids;
}

ParamSet combined_param_table(const ParamSet& base, const std::vector<const Effect*>& effects) {
  std::vector<ParamSpec> specs = base.specs();
  std::vector<double> values = base.values();
  for (const Effect* e : effects) {
    for (std::size_t i = 0; i < e->params().size(); ++i) {
      ParamSpec s = e->params().specs()[i];
      s.name = e->id() + kEffectParamSeparator + s.name;
      specs.push_back(std::move(s));
      values.push_back(e->params()[i]);
    }
  }
  // A stateful effect carries the field from step to step (creep integrates it), so no parameter of the
  // whole is field-only any more.
  if (std::any_of(effects.begin(), effects.end(), [](const Effect* e) { return e->stateful(); }))
    for (ParamSpec& s : specs) s.field_only = false;
  ParamSet table(std::move(specs));
  for (std::size_t i = 0; i < values.size(); ++i) table.set(i, values[i]);
  return table;
}

ParamSet combined_param_table(const ParamSet& base, const std::vector<std::string>& effect_ids) {
  std::vector<std::unique_ptr<Effect>> owned;
  std::vector<const Effect*> effects;
  owned.reserve(effect_ids.size());
  effects.reserve(effect_ids.size());
  for (const auto& id : effect_ids) effects.push_back(owned.emplace_back(make_effect(id)).get());
  return combined_param_table(base, effects);
}

std::vector<std::string> effect_fit_params(const ParamSet& table, const std::string& effect_id) {
  static const std::vector<std::string> kFixed = {"tracker_bias.moving_threshold_px"};
  std::vector<std::string> out;
  const std::string prefix = effect_id + kEffectParamSeparator;
  for (const auto& s : table.specs())
    if (s.name.rfind(prefix, 0) == 0 && std::find(kFixed.begin(), kFixed.end(), s.name) == kFixed.end())
      out.push_back(s.name);
  return out;
}

void EffectModel::rebuild_param_table() {
  std::vector<const Effect*> effects;
  for (const auto& e : effects_) effects.push_back(e.get());
  params_ = combined_param_table(base_->params(), effects);
}

void EffectModel::set_params(const ParamSet& params) {
  if (params.size() != params_.size())
    throw std::invalid_argument("EffectModel '" + id() + "': expected " + std::to_string(params_.size()) +
                                " parameters, got " + std::to_string(params.size()));
  // Validate everything on copies first so a bad table leaves the model unchanged.
  ParamSet base_params = base_->params();
  std::vector<ParamSet> effect_params;
  for (const auto& e : effects_) effect_params.push_back(e->params());
  for (std::size_t i = 0; i < params.size(); ++i) {
    const std::string& name = params.specs()[i].name;
    if (params_.index_of(name) < 0)
      throw std::invalid_argument("EffectModel '" + id() + "' has no parameter '" + name + "'");
    const double value = params[i];
    if (base_params.index_of(name) >= 0) {
      base_params.set(name, value);
      continue;
    }
    for (std::size_t k = 0; k < effects_.size(); ++k) {
      const std::string prefix = effects_[k]->id() + kEffectParamSeparator;
      if (name.rfind(prefix, 0) == 0 && effect_params[k].index_of(name.substr(prefix.size())) >= 0) {
        effect_params[k].set(name.substr(prefix.size()), value);
        break;
      }
    }
  }
  base_->set_params(base_params);
  for (std::size_t k = 0; k < effects_.size(); ++k) effects_[k]->set_params(effect_params[k]);
  rebuild_param_table();
  if (memo_) memo_->set_base_params(base_->params().values());
}

void EffectModel::reset() {
  base_->reset();
  for (auto& e : effects_) e->reset();
  time_s_ = 0.0;
  previous_depth_m_ = 0.0;
  last_penetration_ = Penetration{};
  pending_.reset();
  step_index_ = 0;
  base_steps_ = 0;
}

void EffectModel::remember_base_field(bool on) {
  if (!on) {
    memo_.reset();
  } else if (!memo_) {
    memo_ = std::make_unique<BaseFieldMemo>();
    memo_->set_base_params(base_->params().values());
  }
}

bool EffectModel::acts_after_base(const std::string& param_name) const {
  return std::any_of(effects_.begin(), effects_.end(), [&](const auto& e) {
    const std::string prefix = e->id() + kEffectParamSeparator;
    return !e->acts_on_pose() && param_name.rfind(prefix, 0) == 0;
  });
}

// The base's step, or its remembered field. A step the memo cannot answer after some it did finds the base
// behind: the base is brought up to it first by replaying the remembered poses (they are this run's: every
// earlier step matched).
void EffectModel::step_base(std::size_t step, const Pose& X_EI_seen, double dt, FieldOutput* out) {
  if (memo_ && memo_->replay(step, X_EI_seen, dt, out)) return;
  if (base_steps_ != step) {
    base_->reset();
    for (std::size_t k = 0; k < step; ++k) base_->step(memo_->pose(k), memo_->dt(k), nullptr);
  }
  base_->step(X_EI_seen, dt, out);  // throws on a non-finite pose before any state here changes
  base_steps_ = step + 1;
  if (memo_) memo_->record(step, X_EI_seen, dt, out);
}

void EffectModel::step(const Pose& X_EI, double dt, FieldOutput* out) {
  if (!std::isfinite(dt) || dt < 0.0)
    throw std::invalid_argument("EffectModel::step: dt = " + std::to_string(dt) + " must be finite and >= 0");
  const bool field_needed = std::any_of(effects_.begin(), effects_.end(), [](const auto& e) { return e->stateful(); });
  if (out == nullptr && field_needed) out = &scratch_field_;
  Pose X_EI_seen = X_EI;
  for (const auto& e : effects_) X_EI_seen = e->corrected_pose(X_EI_seen);
  step_base(step_index_, X_EI_seen, dt, out);
  time_s_ += dt;
  const std::size_t step = step_index_++;
  for (auto& e : effects_)
    if (e->observes_steps()) e->observe_step(X_EI_seen, penetration_at(step, X_EI_seen));
  if (out == nullptr) {  // no field wanted, none of the effects carries state: the penetration can wait
    pending_.emplace(step, X_EI_seen);
    return;
  }
  if (pending_) previous_depth_m_ = penetration_at(pending_->first, pending_->second).depth_m;
  pending_.reset();
  last_penetration_ = penetration_at(step, X_EI_seen);

  EffectContext ctx;
  ctx.sensor = sensor_.get();
  ctx.dt_s = dt;
  ctx.time_s = time_s_;
  ctx.X_EI = X_EI_seen;
  ctx.indenter = indenter_.get();
  ctx.depth_m = last_penetration_.depth_m;
  ctx.contact_centre_E = last_penetration_.centre_E;
  ctx.marker_in_contact = &out->marker_in_contact;
  const bool any_marker =
      std::any_of(out->marker_in_contact.begin(), out->marker_in_contact.end(), [](std::uint8_t c) { return c != 0; });
  ctx.in_contact = last_penetration_.penetrating || any_marker;
  ctx.loading = ctx.depth_m > previous_depth_m_;
  previous_depth_m_ = ctx.depth_m;

  for (auto& e : effects_) e->apply(ctx, out->disp_px);
}

// The penetration depends on the pose alone and costs more than the base model for a finely sampled
// indenter (the TacTip's flat surface: 15k points); fits replay the same pose sequence from reset() hundreds of
// times, so it is remembered per step and reused when the pose is bit-identical (the result is then identical).
const Penetration& EffectModel::penetration_at(std::size_t step, const Pose& X_EI) const {
  if (step < penetration_cache_.size() && penetration_cache_[step].first.matrix() == X_EI.matrix())
    return penetration_cache_[step].second;
  if (step >= penetration_cache_.size()) penetration_cache_.resize(step + 1);
  penetration_cache_[step] = {X_EI, cached_penetration(sensor_, indenter_, X_EI)};
  return penetration_cache_[step].second;
}

const Penetration& EffectModel::last_penetration() const {
  if (pending_) {
    last_penetration_ = penetration_at(pending_->first, pending_->second);
    previous_depth_m_ = last_penetration_.depth_m;
    pending_.reset();
  }
  return last_penetration_;
}

std::unique_ptr<ShearModel> EffectModel::clone() const {
  std::vector<std::unique_ptr<Effect>> effects;
  for (const auto& e : effects_) effects.push_back(e->clone());
  // A base behind its memo's replays is brought up to this step first (the copy has no memo to replay from).
  std::unique_ptr<ShearModel> base = base_->clone();
  if (base_steps_ != step_index_) {
    base->reset();
    for (std::size_t k = 0; k < step_index_; ++k) base->step(memo_->pose(k), memo_->dt(k), nullptr);
  }
  auto copy = std::make_unique<EffectModel>(std::move(base), std::move(effects), sensor_, indenter_);
  copy->time_s_ = time_s_;
  copy->previous_depth_m_ = previous_depth_m_;
  copy->last_penetration_ = last_penetration_;
  copy->pending_ = pending_;
  // Not the penetration cache: it only saves time, gives identical results when rebuilt, and grows with the
  // steps taken, so copying it made the workbench's checkpoints (a clone every 16 steps) cost O(path) each.
  copy->step_index_ = step_index_;
  copy->base_steps_ = step_index_;
  return copy;
}

// ---------------------------------------------------------------------------------------- registry

namespace {
struct Registered {
  std::string id;
  std::function<std::unique_ptr<Effect>()> make;
};
const std::vector<Registered>& registry() {
  static const std::vector<Registered> r = {
      {"viscoelastic_creep", effects::make_viscoelastic_creep},
      {"lens_distortion", effects::make_lens_distortion},
      {"subsurface_markers", effects::make_subsurface_markers},
      {"gravity_preload", effects::make_gravity_preload},
      {"edge_constraint", effects::make_edge_constraint},
      {"load_stiffening", effects::make_load_stiffening},
      {"tracker_bias", effects::make_tracker_bias},
      {"camera_misalignment", effects::make_camera_misalignment},
      {"tool_frame", effects::make_tool_frame},
      {"pin_lever", effects::make_pin_lever},
      {"dome_sway", effects::make_dome_sway},
      {"spread_saturation", effects::make_spread_saturation},
      {"skin_indentation", effects::make_skin_indentation},
  };
  return r;
}
}  // namespace

const std::vector<std::string>& effect_ids() {
  static const std::vector<std::string> ids = [] {
    std::vector<std::string> v;
    for (const auto& r : registry()) v.push_back(r.id);
    return v;
  }();
  return ids;
}

bool any_acts_on_pose(const std::vector<std::string>& effect_ids) {
  return std::any_of(effect_ids.begin(), effect_ids.end(),
                     [](const std::string& id) { return make_effect(id)->acts_on_pose(); });
}

std::unique_ptr<Effect> make_effect(const std::string& id) {
  for (const auto& r : registry())
    if (r.id == id) return r.make();
  std::vector<std::string> known;
  for (const auto& r : registry()) known.push_back(r.id);
  throw std::invalid_argument("unknown effect '" + id + "'" + did_you_mean(id, known) +
                              " (known: " + join(known, ", ") + ")");
}

std::unique_ptr<EffectModel> wrap_with_effects(std::unique_ptr<ShearModel> base, const std::vector<std::string>& ids,
                                               std::shared_ptr<const Sensor> sensor,
                                               std::shared_ptr<const Indenter> indenter) {
  std::vector<std::unique_ptr<Effect>> effects;
  effects.reserve(ids.size());
  for (const auto& id : ids) effects.push_back(make_effect(id));
  return std::make_unique<EffectModel>(std::move(base), std::move(effects), std::move(sensor), std::move(indenter));
}

}  // namespace sb
