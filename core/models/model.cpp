// The model registry: ids, default parameter tables, and single-sensor ShearModel instances, each a
// batch of one of the batched kernels (hydroshear.hpp, fots.hpp, tacsl.hpp).
#include "core/models/model.hpp"

#include "core/base/closest_name.hpp"

#include <stdexcept>

#include "core/models/fots.hpp"
#include "core/models/hydroshear.hpp"
#include "core/models/tacsl.hpp"

namespace sb {

namespace {

// Adapts a batch with one slot to ShearModel. Batch: set_params, params, reset, step(span...). The sensor's
// output stage (pins at depth, a perspective camera; the identity for the GelSight Mini) is applied here, the
// one place every model's field passes, so the batched kernels stay as they are.
template <class Batch>
class SingleSlotModel final : public ShearModel {
 public:
  SingleSlotModel(std::string id, std::shared_ptr<Batch> batch, std::shared_ptr<const Sensor> sensor)
      : id_(std::move(id)), batch_(std::move(batch)), sensor_(std::move(sensor)) {}
  std::string id() const override { return id_; }
  const ParamSet& params() const override { return batch_->params(); }
  void set_params(const ParamSet& params) override { batch_->set_params(params); }
  void reset() override { batch_->reset(); }
  void step(const Pose& X_EI, double dt, FieldOutput* out) override {
    disp_.resize(batch_->markers());
    if (out) {
      batch_->step(std::span<const Pose>(&X_EI, 1), dt, disp_, std::span<FieldOutput>(out, 1));
      if (!sensor_->output_stage.identity()) sensor_->output_stage.apply(out->disp_px);
    } else if constexpr (requires { requires Batch::kFieldOptional; }) {
      batch_->step(std::span<const Pose>(&X_EI, 1), dt, {}, {});  // the state only
    } else {
      batch_->step(std::span<const Pose>(&X_EI, 1), dt, disp_, {});
    }
  }
  std::unique_ptr<ShearModel> clone() const override {
    return std::make_unique<SingleSlotModel>(id_, std::make_shared<Batch>(*batch_), sensor_);
  }

 private:
  std::string id_;
  std::shared_ptr<Batch> batch_;
  std::shared_ptr<const Sensor> sensor_;
  std::vector<Vec2> disp_;
};

}  // namespace

const std::vector<std::string>& model_ids() {
  static const std::vector<std::string> ids = {"hydroshear",        "fots",
                                               "fots-reimpl",       "tacsl",
                                               "tacsl-normalized",  "hydroshear-layer",
                                               "hydroshear-stick",  "hydroshear-layer-stick",
                                               "hydroshear-contact"};
  return ids;
}

std::string model_ids_text(const std::string& separator) {
  std::string text;
  for (const std::string& m : model_ids()) text += (text.empty() ? "" : separator) + m;
  return text;
}

ParamSet default_params(const std::string& id) {
  if (id == "hydroshear") return ParamSet(hydroshear_param_specs());
  if (id == "hydroshear-layer") return ParamSet(hydroshear_param_specs(true));
  if (id == "hydroshear-stick") return ParamSet(hydroshear_param_specs(false, true));
  if (id == "hydroshear-layer-stick") return ParamSet(hydroshear_param_specs(true, true));
  if (id == "hydroshear-contact") return ParamSet(hydroshear_param_specs(true, true, true));
  if (id == "fots") return ParamSet(fots_param_specs());
  if (id == "fots-reimpl") return ParamSet(fots_reimpl_param_specs());
  if (id == "tacsl") return ParamSet(tacsl_param_specs(false));
  if (id == "tacsl-normalized") return ParamSet(tacsl_param_specs(true));
  throw std::invalid_argument("unknown model id '" + id + "'" + did_you_mean(id, model_ids()) +
                              " (known: " + model_ids_text(", ") + ")");
}

std::unique_ptr<ShearModel> make_model(const std::string& id, std::shared_ptr<const Sensor> sensor,
                                       std::shared_ptr<const Indenter> indenter) {
  const ParamSet p = default_params(id);
  if (id.starts_with("hydroshear"))
    return std::make_unique<SingleSlotModel<HydroShearBatch>>(
        id, std::make_shared<HydroShearBatch>(sensor, indenter, 1, p), sensor);
  if (id == "fots" || id == "fots-reimpl") {
    const auto v = id == "fots" ? FotsVariant::Original : FotsVariant::Reimpl;
    return std::make_unique<SingleSlotModel<FotsBatch>>(id, std::make_shared<FotsBatch>(v, sensor, indenter, 1, p),
                                                        sensor);
  }
  return std::make_unique<SingleSlotModel<TacslBatch>>(
      id, std::make_shared<TacslBatch>(id == "tacsl-normalized", sensor, indenter, 1, p), sensor);
}

}  // namespace sb
