#pragma once
// A fit's least-squares cost per iteration, kept per stage. Each stage fits its own parameters on its own
// residuals (and the joint stage every parameter), so one stage's cost is not comparable with the next one's:
// drawn as one curve, a stage that starts at 4.6e3 after one that ended at 184 reads as divergence. The fit
// panel draws each stage relative to its own start instead. GL-free, tested in tests/test_stage_losses.cpp.
#include <string>
#include <vector>

namespace sb {

struct StageLosses {
  std::string stage;         // the stage's name, as FitProgress reports it
  std::vector<float> costs;  // Ceres cost after each iteration reported in this stage, in order
};

// Appends `cost` to the last stage when that is `stage`, else starts a stage of that name (a name seen before
// after another stage starts a new run: the same stage run twice is two runs).
void append_stage_loss(std::vector<StageLosses>& curve, const std::string& stage, double cost);

// Each cost divided by the stage's first (1 at the start; 0.25: the stage cut its cost to a quarter). A first
// cost of 0 or less (a perfect start) gives 1 everywhere the cost is 0 and leaves other values as they are.
std::vector<float> relative_to_stage_start(const StageLosses& stage);

}  // namespace sb
