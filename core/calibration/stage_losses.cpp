#include "core/calibration/stage_losses.hpp"

namespace sb {

void append_stage_loss(std::vector<StageLosses>& curve, const std::string& stage, double cost) {
  if (curve.empty() || curve.back().stage != stage) curve.push_back({stage, {}});
  curve.back().costs.push_back(static_cast<float>(cost));
}

std::vector<float> relative_to_stage_start(const StageLosses& stage) {
  std::vector<float> out = stage.costs;
  if (out.empty()) return out;
  const float start = out.front();
  for (float& c : out) c = start > 0 ? c / start : (c == 0 ? 1.0f : c);
  return out;
}

}  // namespace sb
