// What a fit runs for a model (fit.hpp): the stage table, the joint refinement and the held parameters, from
// the model family's descriptor (core/models/model_family.hpp) and the effects' tables. The engine that runs the
// stages is fit_engine.cpp.
#include "core/calibration/fit.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <stdexcept>

#include "core/base/strings.hpp"
#include "core/data/tsd.hpp"
#include "core/effects/effects.hpp"
#include "core/effects/model_spec.hpp"
#include "core/models/model_family.hpp"

namespace sb {

std::vector<FitStage> fit_stages(const std::string& id) {
  const ModelSpec spec = parse_model_spec(id);
  std::vector<FitStage> stages = model_form(spec.form).fit_stages;
  if (spec.effects.empty()) return stages;
  const ParamSet table = model_spec_params(id);
  FitStage effects{"effects", {}, tsd_motions(), false, {}};
  for (const auto& e : spec.effects)
    for (const auto& name : effect_fit_params(table, e)) effects.params.push_back(name);
  if (!effects.params.empty()) stages.push_back(std::move(effects));
  return stages;
}

FitStage joint_stage(const std::string& id, bool px_scale) {
  FitStage j{"joint", {}, {"dilation", "shear", "twist", "roll", "slip"}, false, {}};
  for (const auto& s : fit_stages(id))
    for (const auto& p : s.params)
      if (std::find(j.params.begin(), j.params.end(), p) == j.params.end()) j.params.push_back(p);
  // A form followed by effects fits the image scale through its effects, if at all.
  const ModelForm* form = find_model_form(id);
  if (px_scale && form != nullptr)
    j.params.insert(j.params.end(), form->px_scale_params.begin(), form->px_scale_params.end());
  return j;
}

void hold_after_first_stage(const std::vector<std::string>& hold, std::vector<FitStage>* stages) {
  std::set<std::string> fitted;
  for (FitStage& s : *stages) {
    std::vector<std::string> kept;
    for (const std::string& p : s.params)
      if (fitted.count(p) == 0 || std::find(hold.begin(), hold.end(), p) == hold.end()) kept.push_back(p);
    for (const std::string& p : s.params) fitted.insert(p);
    s.params = std::move(kept);
  }
  std::erase_if(*stages, [](const FitStage& s) { return s.params.empty(); });
}

CalibrationResult fit_model(const std::string& model_id, std::shared_ptr<const Sensor> sensor,
                            const std::vector<FitSample>& samples, const ParamSet& start, const FitOptions& o) {
  const auto& table = fit_stages(model_id);
  std::vector<FitStage> stages;
  for (const auto& name : o.stages) {
    const bool known = name == "joint" ||
                       std::any_of(table.begin(), table.end(), [&](const FitStage& s) { return s.name == name; });
    if (!known) {
      std::vector<std::string> names;
      names.reserve(table.size());
      for (const auto& s : table) names.push_back(s.name);
      throw std::invalid_argument("fit: model '" + model_id + "' has no stage '" + name +
                                  "' (stages: " + join(names, ", ") + ", joint)");
    }
  }
  const auto wanted = [&](const std::string& n) {
    return o.stages.empty() || std::find(o.stages.begin(), o.stages.end(), n) != o.stages.end();
  };
  for (const auto& s : table)
    if (wanted(s.name)) stages.push_back(s);
  if (o.joint || (!o.stages.empty() && wanted("joint"))) stages.push_back(joint_stage(model_id, o.fit_px_scale));
  hold_after_first_stage(o.hold, &stages);
  const FitModelFactory make = [&](std::shared_ptr<const Indenter> ind) {
    return make_spec_model(model_id, sensor, std::move(ind));
  };
  return run_fit_stages(model_id, make, stages, samples, start, o);
}

double fit_rmse_px(const std::string& model_id, const std::shared_ptr<const Sensor>& sensor,
                   const std::vector<FitSample>& samples, const ParamSet& params) {
  double sse = 0;
  long n = 0;
  std::vector<double> sse_i(samples.size(), 0.0);
  std::vector<long> n_i(samples.size(), 0);
  // One model per indenter, cloned per sample (building one indexes the indenter's points).
  std::map<const Indenter*, std::unique_ptr<ShearModel>> prototypes;
  for (const auto& s : samples)
    if (!prototypes.count(s.indenter.get()))
      prototypes[s.indenter.get()] = make_spec_model(model_id, sensor, s.indenter);
  tbb::parallel_for(0, static_cast<int>(samples.size()), [&](int i) {
    auto model = prototypes.at(samples[i].indenter.get())->clone();
    model->set_params(params);
    const auto pred = simulate_sample(*model, samples[i]);
    const std::size_t m = samples[i].meas_px.front().size();
    for (int f : active_marker_frames(samples[i].meas_px)) {
      sse_i[i] += (pred[f / m][f % m] - samples[i].meas_px[f / m][f % m]).squaredNorm();
      ++n_i[i];
    }
  });
  for (std::size_t i = 0; i < samples.size(); ++i) {
    sse += sse_i[i];
    n += n_i[i];
  }
  return n ? std::sqrt(sse / n) : 0.0;
}

}  // namespace sb
