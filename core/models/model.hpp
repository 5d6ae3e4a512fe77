#pragma once
// The one engine-agnostic shear-model interface. A model maps the pose history of an indenter in the
// elastomer frame, X_EI(t0..t), to the displacement of every marker in image pixels.
// Implementations: hydroshear, fots, fots-reimpl, tacsl, tacsl-normalized (see make_model).
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/base/params.hpp"
#include "core/geometry/indenter.hpp"
#include "core/sensor/sensor.hpp"

namespace sb {

enum class PointState : std::uint8_t { kFree = 0, kStick = 1, kSlip = 2 };

// One sensor's output for one step. Diagnostics are filled by models that have them (HydroShear's
// tracked points); others leave them empty.
struct FieldOutput {
  std::vector<Vec2> disp_px;  // per marker (du, dv) in image pixels
  std::vector<std::uint8_t> marker_in_contact;
  std::vector<Vec3> p_EP;       // tracked points in E (only those near the gel)
  std::vector<Vec3> anchor_EP;  // their anchors (where they stuck)
  std::vector<PointState> point_state;
};

class ShearModel {
 public:
  virtual ~ShearModel() = default;
  virtual std::string id() const = 0;
  virtual const ParamSet& params() const = 0;
  // Takes effect at the next step; does not reset the state (callers replay from the start).
  virtual void set_params(const ParamSet& params) = 0;
  virtual void reset() = 0;
  // One step to the pose X_EI (indenter in elastomer) after dt seconds. Throws std::invalid_argument
  // on a non-finite pose. out == nullptr: no field is wanted at this step (nothing measured there); the
  // state still advances exactly as with a field, and a model may skip computing the field.
  virtual void step(const Pose& X_EI, double dt, FieldOutput* out) = 0;
  virtual std::unique_ptr<ShearModel> clone() const = 0;
};

// The known model ids, in display order.
const std::vector<std::string>& model_ids();
// "hydroshear | fots | ..." for help texts and errors.
std::string model_ids_text(const std::string& separator = " | ");
// Default parameter table of a model id (throws std::invalid_argument for an unknown id).
ParamSet default_params(const std::string& model_id);
std::unique_ptr<ShearModel> make_model(const std::string& model_id, std::shared_ptr<const Sensor> sensor,
                                       std::shared_ptr<const Indenter> indenter);

}  // namespace sb
