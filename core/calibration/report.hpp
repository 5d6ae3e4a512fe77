#pragma once
// The fidelity table (docs/fidelity.md): every model fitted on a dataset's calibration split
// (core/calibration/fit.hpp) and scored on its validation split (core/calibration/evaluate.hpp), for each dataset,
// beside the HydroShear paper's own table for scale, with a reading generated from the numbers.
#include <string>
#include <vector>

#include "core/calibration/evaluate.hpp"
#include "core/calibration/fit.hpp"

namespace sb {

struct DatasetFidelity {
  std::string dataset;  // name
  std::string dir;
  std::vector<CalibrationResult> fits;     // per model, in model order
  std::vector<EvaluationResult> fitted;    // validation, fitted parameters
  std::vector<EvaluationResult> defaults;  // validation, default parameters
  double seconds = 0;
};

struct FidelityOptions {
  std::vector<std::string> dataset_dirs;
  std::vector<std::string> models;  // empty: all
  FitOptions fit;
  std::vector<std::string> calibration_ids;  // non-empty: these samples calibrate, the others validate
  std::vector<std::string> validation_ids;   // non-empty (with calibration_ids): only these validate
  std::string data_root;
  std::function<void(const std::string&)> log;
};

std::vector<DatasetFidelity> run_fidelity(const FidelityOptions& options);

// The Markdown page. `analysis` (hand-written Markdown) is inserted after the generated reading.
std::string fidelity_markdown(const std::vector<DatasetFidelity>& results, const FidelityOptions& options,
                              const std::string& analysis);

// The generated reading of one dataset: per motion, the best model by RMSE and by CS, and where the
// fitted HydroShear is not the lowest RMSE, by how much.
std::string fidelity_reading(const DatasetFidelity& r);

}  // namespace sb
