// The evidence of the answer's effects (effect_evidence.hpp): the registry of readers and the runs they read.
#include "core/loop/effect_evidence.hpp"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <stdexcept>
#include <string_view>

#include <tbb/parallel_for.h>

#include "core/effects/effect_catalogue.hpp"
#include "core/effects/effects.hpp"
#include "core/effects/model_spec.hpp"
#include "core/loop/fingerprint_camera_misalignment.hpp"
#include "core/loop/fingerprint_dome_sway.hpp"
#include "core/loop/fingerprint_edge_constraint.hpp"
#include "core/loop/fingerprint_gravity_preload.hpp"
#include "core/loop/fingerprint_load_stiffening.hpp"
#include "core/loop/fingerprint_pin_lever.hpp"
#include "core/loop/fingerprint_skin_indentation.hpp"
#include "core/loop/fingerprint_spread_saturation.hpp"
#include "core/loop/fingerprint_tool_frame.hpp"
#include "core/loop/fingerprint_tracker_bias.hpp"
#include "core/loop/fingerprints.hpp"
#include "core/loop/loop_samples.hpp"

namespace sb {

namespace {

std::vector<FingerprintSample> fingerprint_view(const EvidenceSplit& split) {
  std::vector<FingerprintSample> fs;
  fs.reserve(split.samples.size());
  for (const auto& s : split.samples) fs.push_back(s.fp);
  return fs;
}

// Creep, lens and subsurface markers: their fingerprints (fingerprints.hpp) are the evidence, read against the
// answer's field without them; found when the fingerprint is (FingerprintCheck::consistent).
EffectEvidence from_fingerprint(const std::string& id, const Sensor& sensor, const EvidenceSplit& calibration,
                                const EvidenceSplit& validation, const FittedParam& fitted) {
  const auto c = fingerprint_check(id, sensor, fingerprint_view(calibration), fingerprint_view(validation));
  EffectEvidence e;
  e.effect = id;
  e.looked_at = c->evidence;
  e.quantity = c->param;
  e.fitted = fitted(c->param);
  e.calibration.estimate = c->calibration;
  e.validation.estimate = c->validation;
  e.calibration.noise_px = calibration.noise_px;
  e.validation.noise_px = validation.noise_px;
  e.found = c->consistent;
  e.verdict = (e.found ? "found: " : "not found: ") + c->verdict;
  return e;
}

using Reader = EffectEvidence (*)(const Sensor&, const EvidenceSplit&, const EvidenceSplit&, const FittedParam&);

// One entry per catalogued effect (the catalogue's ids; tests/test_effect_evidence.cpp checks them against it).
struct EvidenceEntry {
  std::string_view effect_id;
  bool needs_marker_depth;
  Reader read;  // nullptr: the effect's fingerprint (from_fingerprint)
};

constexpr EvidenceEntry kEntries[] = {
    {"viscoelastic_creep", false, nullptr},
    {"lens_distortion", false, nullptr},
    {"subsurface_markers", false, nullptr},
    {"tool_frame", false, tool_frame_evidence},
    {"load_stiffening", false, load_stiffening_evidence},
    {"dome_sway", false, dome_sway_evidence},
    {"skin_indentation", true, skin_indentation_evidence},
    {"pin_lever", true, pin_lever_evidence},
    {"tracker_bias", false, tracker_bias_evidence},
    {"gravity_preload", false, gravity_preload_evidence},
    {"camera_misalignment", false, camera_misalignment_evidence},
    {"edge_constraint", false, edge_constraint_evidence},
    {"spread_saturation", false, spread_saturation_evidence},
};

const EvidenceEntry& entry(const std::string& effect_id) {
  for (const auto& e : kEntries)
    if (e.effect_id == effect_id) return e;
  throw std::invalid_argument("no evidence reader for effect '" + effect_id + "'");
}

double tilt_of(const Pose& X_EI) {
  const double c = (X_EI.linear() * Vec3::UnitZ()).dot(Vec3::UnitZ());
  return std::acos(std::clamp(c, -1.0, 1.0));
}

}  // namespace

std::vector<std::string> evidenced_effects() {
  std::vector<std::string> ids;
  for (const auto& e : kEntries) ids.emplace_back(e.effect_id);
  return ids;
}

bool evidence_needs_marker_depth(const std::string& effect_id) { return entry(effect_id).needs_marker_depth; }

EvidenceSplit evidence_split(const Sensor& sensor, const std::vector<FitSample>& samples, bool marker_depth) {
  std::vector<FingerprintSample> fs = fingerprint_samples(sensor, samples);
  EvidenceSplit split;
  split.noise_px = tracker_noise_px(fs);
  split.samples.resize(samples.size());
  tbb::parallel_for(0, static_cast<int>(samples.size()), [&](int i) {
    const FitSample& s = samples[static_cast<std::size_t>(i)];
    EvidenceSample& e = split.samples[static_cast<std::size_t>(i)];
    e.fp = std::move(fs[static_cast<std::size_t>(i)]);
    bool touched = false;
    Vec2 first = Vec2::Zero();
    for (std::size_t k = 0; k < s.X_EI.size(); ++k) {
      const Pose& X_EI = s.X_EI[k];
      e.depth_m.push_back(indenter_penetration(*sensor.gel_sdf, *s.indenter, X_EI).depth_m);
      e.tilt_rad.push_back(tilt_of(X_EI));
      e.approach_xy.push_back((X_EI.linear() * Vec3::UnitZ()).head<2>());
      const Vec2 xy = X_EI.translation().head<2>();
      if (e.fp.in_contact[k] != 0 && !touched) first = xy, touched = true;
      e.slide_m.push_back(touched ? Vec2(xy - first) : Vec2::Zero());
    }
    if (!marker_depth) return;
    EffectContext c;
    c.sensor = &sensor;
    c.indenter = s.indenter.get();
    for (std::size_t k = 0; k < s.X_EI.size(); ++k) {
      c.X_EI = s.X_EI[k];
      e.marker_depth_m.push_back(e.fp.in_contact[k] != 0 ? effects::marker_penetration(c)
                                                         : std::vector<double>(sensor.p_EM.size(), 0.0));
    }
  });
  return split;
}

EffectEvidence read_evidence(const std::string& effect_id, const Sensor& sensor, const EvidenceSplit& calibration,
                             const EvidenceSplit& validation, const FittedParam& fitted) {
  const EvidenceEntry& e = entry(effect_id);
  if (!make_effect(effect_id)->acts_on(sensor)) {
    EffectEvidence none;
    none.effect = effect_id;
    none.looked_at = "the sensor";
    none.verdict =
        "not found: the effect does not act on this sensor (a correction of its form, if it changes the field)";
    return none;
  }
  if (e.read == nullptr) return from_fingerprint(effect_id, sensor, calibration, validation, fitted);
  return e.read(sensor, calibration, validation, fitted);
}

namespace {

// Sets pred_px of every sample to the field of `model_id` at `params`.
void set_model_field(EvidenceSplit* split, const std::string& model_id, const ParamSet& params,
                     const std::shared_ptr<const Sensor>& sensor, const std::vector<FitSample>& samples) {
  const SampleModelFactory make = spec_model_factory(model_id, sensor);
  ParamSet table = model_spec_params(model_id);
  copy_shared(params, &table);
  tbb::parallel_for(0, static_cast<int>(samples.size()), [&](int i) {
    const auto idx = static_cast<std::size_t>(i);
    auto model = make(samples[idx], idx);
    model->set_params(table);
    split->samples[idx].fp.pred_px = simulate_sample(*model, samples[idx]);
  });
}

}  // namespace

std::vector<EffectEvidence> answer_evidence(const std::shared_ptr<const Sensor>& sensor, const std::string& form,
                                            const std::vector<std::string>& selected, const ParamSet& params,
                                            const std::vector<FitSample>& calibration,
                                            const std::vector<FitSample>& validation) {
  std::vector<EffectEvidence> out;
  if (selected.empty()) return out;
  const bool marker_depth = std::any_of(selected.begin(), selected.end(), evidence_needs_marker_depth);
  EvidenceSplit cal = evidence_split(*sensor, calibration, marker_depth),
                val = evidence_split(*sensor, validation, marker_depth);
  for (const auto& id : selected) {
    std::vector<std::string> others;
    std::copy_if(selected.begin(), selected.end(), std::back_inserter(others), [&](const auto& o) { return o != id; });
    const std::string without = ModelSpec{form, others}.id();
    set_model_field(&cal, without, params, sensor, calibration);
    set_model_field(&val, without, params, sensor, validation);
    const std::string prefix = id + kEffectParamSeparator;
    const FittedParam fitted = [&](const std::string& name) {
      const int i = params.index_of(prefix + name);
      return i < 0 ? kEvidenceNaN : params[static_cast<std::size_t>(i)];
    };
    out.push_back(read_evidence(id, *sensor, cal, val, fitted));
  }
  return out;
}

}  // namespace sb
