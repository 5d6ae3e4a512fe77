#include "core/effects/base_field_memo.hpp"

#include <stdexcept>
#include <string>

namespace sb {

void BaseFieldMemo::set_base_params(const std::vector<double>& values) {
  if (values == base_values_) return;
  base_values_ = values;
  steps_.clear();
}

// Bit-identical pose and dt only: the memo stands in for the base's own arithmetic, so anything else would
// change the fit's numbers.
bool BaseFieldMemo::replay(std::size_t step, const Pose& X_EI, double dt, FieldOutput* out) const {
  if (step >= steps_.size()) return false;
  const Step& s = steps_[step];
  if (s.dt != dt || s.X_EI.matrix() != X_EI.matrix()) return false;
  if (out == nullptr) return true;
  if (!s.has_field) return false;
  out->disp_px = s.disp_px;
  out->marker_in_contact = s.marker_in_contact;
  out->p_EP.clear();
  out->anchor_EP.clear();
  out->point_state.clear();
  return true;
}

void BaseFieldMemo::record(std::size_t step, const Pose& X_EI, double dt, const FieldOutput* out) {
  if (step > steps_.size())
    throw std::logic_error("BaseFieldMemo::record: step " + std::to_string(step) + " after " +
                           std::to_string(steps_.size()) + " recorded steps");
  steps_.resize(step);
  Step& s = steps_.emplace_back();
  s.X_EI = X_EI;
  s.dt = dt;
  s.has_field = out != nullptr;
  if (out != nullptr) {
    s.disp_px = out->disp_px;
    s.marker_in_contact = out->marker_in_contact;
  }
}

}  // namespace sb
