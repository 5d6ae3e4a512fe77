#pragma once
// The batched kernels (HydroShearBatch, FotsBatch, TacslBatch, ...) behind one interface: they share the
// step signature, not a base class. Used by the public API's SensorModel (core/api), which also times the
// benchmark workload through it.
#include <memory>
#include <span>
#include <string>

#include "core/base/params.hpp"
#include "core/geometry/indenter.hpp"
#include "core/models/model.hpp"
#include "core/models/phase_profile.hpp"
#include "core/sensor/sensor.hpp"

namespace sb {

class AnyBatch {
 public:
  virtual ~AnyBatch() = default;
  virtual int slots() const = 0;
  virtual int markers() const = 0;
  virtual const ParamSet& params() const = 0;
  virtual void reset() = 0;
  virtual void reset_slot(int slot) = 0;
  // Phase timing of later steps into `profile` (nullptr: off). Not owned.
  virtual void set_profile(PhaseProfile* profile) = 0;
  // X_EI[slot]; disp_px[slot * markers() + j]; diagnostics empty or one per slot. Throws std::invalid_argument
  // on a non-finite pose. The field is the kernel's, before the sensor's output stage (make_model applies
  // that; so does the API).
  virtual void step(std::span<const Pose> X_EI, double dt, std::span<Vec2> disp_px,
                    std::span<FieldOutput> diagnostics) = 0;
};

// Whether `model_id` (a model_ids() entry) has a batched kernel: every model form does.
bool has_batch(const std::string& model_id);
// The batch of `slots` sensors of model `model_id` at `params`. Throws std::invalid_argument for an unknown id.
std::unique_ptr<AnyBatch> make_batch(const std::string& model_id, const std::shared_ptr<const Sensor>& sensor,
                                     const std::shared_ptr<const Indenter>& indenter, int slots,
                                     const ParamSet& params);

}  // namespace sb
