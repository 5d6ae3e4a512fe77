#pragma once
// The effect catalogue: physically motivated, parametric corrections that wrap any ShearModel.
//
// An Effect post-processes the marker displacement field of a base model, once per step, in order,
// so effects compose: disp <- effect_n(... effect_1(base(X_EI)) ...). Every effect's defaults are
// "no effect", so a wrapped model at default parameters reproduces its base model exactly. The
// physics of each effect, its parameters and the attribution rule are in docs/effects.md.
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/base/params.hpp"
#include "core/base/typed_params.hpp"
#include "core/effects/base_field_memo.hpp"
#include "core/geometry/indenter.hpp"
#include "core/models/model.hpp"
#include "core/sensor/sensor.hpp"

namespace sb {

// How deep the indenter is in the gel and where, for one pose.
struct Penetration {
  double depth_m = 0.0;      // max over the indenter of -phi_E (>= 0; 0 when not touching)
  bool penetrating = false;  // depth_m > 0
  Vec2 centre_E{0.0, 0.0};   // xy in E: penetration-weighted centre of the touching points;
                             // the xy of the lowest point when not touching
  double radius_m = 0.0;     // largest xy distance of a touching point from centre_E (the contact edge
                             // of a round contact; 0 when not touching)
};

// Evaluates the gel SDF phi_E at the indenter's surface samples and mesh vertices placed by X_EI
// (those with z <= 0 only: the gel occupies z <= 0 in E).
// Throws std::invalid_argument when the indenter has neither samples nor vertices.
Penetration indenter_penetration(const Sdf& gel_sdf_E, const Indenter& indenter, const Pose& X_EI);

// What an effect may look at during one step. Pointers stay valid for the duration of apply().
struct EffectContext {
  const Sensor* sensor = nullptr;  // markers (px and p_EM), camera, gel size
  double dt_s = 0.0;               // this step's duration
  double time_s = 0.0;             // time since reset, including this step
  Pose X_EI = Pose::Identity();
  double depth_m = 0.0;                                          // indenter penetration (Penetration)
  bool in_contact = false;                                       // depth > 0 or any marker in contact
  Vec2 contact_centre_E{0.0, 0.0};                               // xy in E (metres)
  bool loading = false;                                          // depth increased this step (else held/unloading)
  const std::vector<std::uint8_t>* marker_in_contact = nullptr;  // the base model's flags; may be empty
  const Indenter* indenter = nullptr;                            // its shape (phi_I) at X_EI
};

class Effect {
 public:
  virtual ~Effect() = default;
  virtual std::string id() const = 0;
  // A short statement of the physical mechanism and its equation (shown in the GUI and docs).
  virtual std::string physics() const = 0;
  const ParamSet& params() const { return params_; }
  // Copies the values of `params` by name; it must hold exactly this effect's parameter names
  // (std::invalid_argument otherwise). Out-of-range values throw as ParamSet::set does.
  void set_params(const ParamSet& params);
  // Clears any state carried between steps (filters); stateless effects do nothing.
  virtual void reset() {}
  // True for an effect that carries state between steps (it overrides reset()): it must see every step's
  // field, so a model wearing it computes the field even where the caller wants none.
  virtual bool stateful() const { return false; }
  // A pose effect corrects the recorded pose before the base model steps (the robot's real pivot): the
  // pose the base sees, in effect order. The others return X_EI and act on the field only.
  virtual bool acts_on_pose() const { return false; }
  // False when the effect is the identity on every field of this sensor (pins on the surface for pin_lever):
  // the loop does not try it there.
  virtual bool acts_on(const Sensor& /*sensor*/) const { return true; }
  // True for a pose effect the loop tries only where the poses tilt (tool_frame: its rotation centre matters only
  // when a pose turns, and its zero trades with the centre under a tilt; a user may still give it elsewhere).
  virtual bool needs_tilt() const { return false; }
  virtual Pose corrected_pose(const Pose& X_EI) const { return X_EI; }
  // True for an effect that follows the path between fields (dome_sway's slide): it is shown every step's pose
  // (as the base saw it) and penetration, before apply() and also at steps that want no field. Cheaper than
  // stateful(): the base computes no field for it.
  virtual bool observes_steps() const { return false; }
  virtual void observe_step(const Pose& /*X_EI*/, const Penetration& /*penetration*/) {}
  // Modifies the field in place. disp_px has one entry per sensor marker (std::invalid_argument
  // otherwise, for effects that use marker positions).
  virtual void apply(const EffectContext& ctx, std::vector<Vec2>& disp_px) = 0;
  virtual std::unique_ptr<Effect> clone() const = 0;

 protected:
  explicit Effect(std::vector<ParamSpec> specs) : params_(std::move(specs)) {}
  // Called after set_params has changed params_.
  virtual void params_changed() {}
  ParamSet params_;
};

// An effect whose parameters are a struct of its own (core/base/typed_params.hpp): v() holds them, read again
// whenever they change. `fields` must outlive the effect (a function's static table).
template <typename Values>
class TypedEffect : public Effect {
 protected:
  explicit TypedEffect(const ParamFields<Values>& fields) : Effect(specs_of(fields)), fields_(&fields) {
    read_params(fields, params_, values_);
  }
  const Values& v() const { return values_; }

 private:
  void params_changed() final { read_params(*fields_, params_, values_); }
  const ParamFields<Values>* fields_;  // a function-local static table (the effect's fields()): lives forever
  Values values_{};
};

// Separator between an effect id and its parameter name in the combined table.
inline constexpr char kEffectParamSeparator = '.';

// A ShearModel = base model followed by a list of effects. Its parameter table is the base's (names
// unchanged) followed by each effect's, prefixed "<effect id>.<name>" (e.g. "viscoelastic_creep.tau_s").
class EffectModel final : public ShearModel {
 public:
  // Throws std::invalid_argument for a null base/sensor/indenter, a null effect, a repeated effect id,
  // or a sensor without a gel SDF.
  EffectModel(std::unique_ptr<ShearModel> base, std::vector<std::unique_ptr<Effect>> effects,
              std::shared_ptr<const Sensor> sensor, std::shared_ptr<const Indenter> indenter);

  // "<base id>+<effect id>+..." (just the base id when there are no effects).
  std::string id() const override;
  const ParamSet& params() const override { return params_; }
  void set_params(const ParamSet& params) override;
  void reset() override;
  // The pose effects' corrections, then the base step at the corrected pose, then the effects in order. Throws
  // std::invalid_argument for a negative or non-finite dt. out == nullptr: the base steps without a field unless an
  // effect is stateful (then into a scratch field).
  void step(const Pose& X_EI, double dt, FieldOutput* out) override;
  std::unique_ptr<ShearModel> clone() const override;

  const ShearModel& base() const { return *base_; }
  std::size_t effect_count() const { return effects_.size(); }
  const Effect& effect(std::size_t i) const { return *effects_.at(i); }
  std::vector<std::string> effect_ids() const;
  // The context of the last step (for diagnostics and the GUI).
  const Penetration& last_penetration() const;
  // On: the base's field at every step is remembered (BaseFieldMemo), and a later run with the same base
  // parameters over the same corrected poses replays it instead of stepping the base: a fit's finite difference
  // in an effect's parameter then costs the effects alone. Replayed steps carry no diagnostics (p_EP, anchors,
  // point states), so only fits turn it on. Off by default; clones start with it off.
  void remember_base_field(bool on);
  // True for a parameter of an effect here that acts on the base's field (not on the pose the base sees): the
  // base's field does not depend on it.
  bool acts_after_base(const std::string& param_name) const;

 private:
  void rebuild_param_table();

  std::unique_ptr<ShearModel> base_;
  std::vector<std::unique_ptr<Effect>> effects_;
  std::shared_ptr<const Sensor> sensor_;
  std::shared_ptr<const Indenter> indenter_;
  ParamSet params_;
  double time_s_ = 0.0;
  mutable double previous_depth_m_ = 0.0;
  mutable Penetration last_penetration_;
  // A step without a field (and no stateful effect) leaves its penetration for later: the next step with a
  // field needs its depth (the loading state), last_penetration() its whole. Step index and corrected pose.
  mutable std::optional<std::pair<std::size_t, Pose>> pending_;
  const Penetration& penetration_at(std::size_t step, const Pose& X_EI) const;
  std::size_t step_index_ = 0;                                           // steps since reset()
  mutable std::vector<std::pair<Pose, Penetration>> penetration_cache_;  // per step index: pose and its penetration
  FieldOutput scratch_field_;            // a stateful effect's field when none is wanted
  std::unique_ptr<BaseFieldMemo> memo_;  // remember_base_field
  std::size_t base_steps_ = 0;           // steps the base itself has taken since reset() (fewer after replays)
  void step_base(std::size_t step, const Pose& X_EI_seen, double dt, FieldOutput* out);
};

// True when one of `effect_ids` corrects the pose (Effect::acts_on_pose): the base must run under it, a
// recorded base field cannot stand in for it.
bool any_acts_on_pose(const std::vector<std::string>& effect_ids);

// The registered effect ids, in display order.
const std::vector<std::string>& effect_ids();
// A new effect at its default ("no effect") parameters. Throws std::invalid_argument for an unknown id,
// naming the known ones.
std::unique_ptr<Effect> make_effect(const std::string& id);
// The parameter table of `base` wrapped with these effects at their defaults: the base's names, then
// "<effect id>.<name>" per effect (EffectModel::params() without building a model).
ParamSet combined_param_table(const ParamSet& base, const std::vector<const Effect*>& effects);
ParamSet combined_param_table(const ParamSet& base, const std::vector<std::string>& effect_ids);
// The parameters of `effect_id` in a combined table that a fit may move (full names "<effect>.<name>"): all
// but those that make the output discontinuous (the tracker's moving threshold, docs/effects.md), which stay
// at their defaults.
std::vector<std::string> effect_fit_params(const ParamSet& table, const std::string& effect_id);
// Convenience: wraps `base` with the effects named by `ids`, in that order.
std::unique_ptr<EffectModel> wrap_with_effects(std::unique_ptr<ShearModel> base, const std::vector<std::string>& ids,
                                               std::shared_ptr<const Sensor> sensor,
                                               std::shared_ptr<const Indenter> indenter);

}  // namespace sb
