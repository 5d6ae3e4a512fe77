#pragma once
// The base model's field at every step of one run, remembered for the next run over the same path.
//
// A fit's finite difference in an effect's parameter reruns the whole model, but the effect acts on the base's
// field after the base has stepped: with the base's parameters and the poses it sees unchanged, the base's field
// is the same at every step. EffectModel (effects.hpp) keeps one of these when a fit asks it to
// (EffectModel::remember_base_field) and steps its base only where the memo has nothing for the step.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/geometry/pose.hpp"
#include "core/models/model.hpp"

namespace sb {

class BaseFieldMemo {
 public:
  // The base's parameter values of the coming run: when they differ from the recorded run's, every recorded
  // step is forgotten.
  void set_base_params(const std::vector<double>& values);
  // Writes the field recorded at `step` into `out` (diagnostics cleared: the memo keeps the displacements and
  // contact flags only) and returns true when that step was taken at the same pose and dt, and with a field
  // when one is wanted (out != nullptr). Returns false otherwise and leaves `out` alone.
  bool replay(std::size_t step, const Pose& X_EI, double dt, FieldOutput* out) const;
  // Records `step` (out == nullptr: the state advanced without a field). Every later step is dropped: it followed
  // another path. Steps must be recorded in order: `step` <= the number recorded.
  void record(std::size_t step, const Pose& X_EI, double dt, const FieldOutput* out);

  std::size_t size() const { return steps_.size(); }
  const Pose& pose(std::size_t step) const { return steps_.at(step).X_EI; }
  double dt(std::size_t step) const { return steps_.at(step).dt; }

 private:
  struct Step {
    Pose X_EI;
    double dt = 0;
    bool has_field = false;
    std::vector<Vec2> disp_px;
    std::vector<std::uint8_t> marker_in_contact;
  };
  std::vector<double> base_values_;
  std::vector<Step> steps_;
};

}  // namespace sb
