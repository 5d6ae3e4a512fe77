#include "core/models/any_batch.hpp"

#include <algorithm>
#include <stdexcept>

#include "core/models/fots.hpp"
#include "core/models/hydroshear.hpp"
#include "core/models/tacsl.hpp"

namespace sb {

namespace {

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

}  // namespace

bool has_batch(const std::string& model_id) {
  const auto& ids = model_ids();
  return std::find(ids.begin(), ids.end(), model_id) != ids.end();
}

std::unique_ptr<AnyBatch> make_batch(const std::string& model, const std::shared_ptr<const Sensor>& sensor,
                                     const std::shared_ptr<const Indenter>& indenter, int slots,
                                     const ParamSet& params) {
  if (!has_batch(model)) throw std::invalid_argument("unknown model '" + model + "' (" + model_ids_text(", ") + ")");
  if (model.rfind("hydroshear", 0) == 0)
    return std::make_unique<BatchOf<HydroShearBatch>>(HydroShearBatch(sensor, indenter, slots, params));
  if (model == "fots")
    return std::make_unique<BatchOf<FotsBatch>>(FotsBatch(FotsVariant::Original, sensor, indenter, slots, params));
  if (model == "fots-reimpl")
    return std::make_unique<BatchOf<FotsBatch>>(FotsBatch(FotsVariant::Reimpl, sensor, indenter, slots, params));
  return std::make_unique<BatchOf<TacslBatch>>(
      TacslBatch(model == "tacsl-normalized", sensor, indenter, slots, params));
}

}  // namespace sb
