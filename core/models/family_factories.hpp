#pragma once
// The two factories of a form (model_family.hpp FormFactories) from one constructor of its batched kernel:
// a single-sensor ShearModel is a batch of one slot, and an AnyBatch wraps the batch as it is.
#include <memory>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "core/models/model_family.hpp"

namespace sb {

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

// A batched kernel behind AnyBatch.
template <class Batch>
class BatchOf final : public AnyBatch {
 public:
  explicit BatchOf(Batch b) : batch_(std::move(b)) {}
  int slots() const override { return batch_.slots(); }
  int markers() const override { return batch_.markers(); }
  const ParamSet& params() const override { return batch_.params(); }
  void reset() override { batch_.reset(); }
  void reset_slot(int slot) override { batch_.reset_slot(slot); }
  void set_profile(PhaseProfile* p) override { batch_.set_profile(p); }
  void step(std::span<const Pose> X_EI, double dt, std::span<Vec2> disp, std::span<FieldOutput> diag) override {
    batch_.step(X_EI, dt, disp, diag);
  }

 private:
  Batch batch_;
};

// `construct(sensor, indenter, slots, params)` returns the form's Batch of that many slots.
template <class Batch, class Construct>
FormFactories factories_of(Construct construct) {
  FormFactories f;
  f.make_model = [construct](const std::string& id, std::shared_ptr<const Sensor> sensor,
                             std::shared_ptr<const Indenter> indenter, const ParamSet& params) {
    auto batch = std::make_shared<Batch>(construct(sensor, indenter, 1, params));
    return std::unique_ptr<ShearModel>(std::make_unique<SingleSlotModel<Batch>>(id, std::move(batch), sensor));
  };
  f.make_batch = [construct](const std::shared_ptr<const Sensor>& sensor,
                             const std::shared_ptr<const Indenter>& indenter, int slots, const ParamSet& params) {
    return std::unique_ptr<AnyBatch>(std::make_unique<BatchOf<Batch>>(construct(sensor, indenter, slots, params)));
  };
  return f;
}

}  // namespace sb
