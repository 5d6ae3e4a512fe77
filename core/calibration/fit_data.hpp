#pragma once
// Loading a tsd/1 dataset for a fit. This is where the split rule is kept for files: only samples whose
// split is "calibration" are ever read (validation CSVs are not opened), and fit_model then refuses any
// sample that is not from the calibration split.
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "core/calibration/fit.hpp"
#include "core/data/tsd.hpp"

namespace sb {

struct FitData {
  std::shared_ptr<const Sensor> sensor;
  std::map<std::string, std::shared_ptr<const Indenter>> indenters;  // by dataset indenter name
  std::vector<FitSample> samples;                                    // calibration only, dataset order
};

// The dataset's sensor (flat pad or its gel mesh) with its marker layout.
std::shared_ptr<const Sensor> dataset_sensor(const Dataset& ds);
// Builds each indenter the samples with `split` use (all samples when split is empty) from its mesh.
std::map<std::string, std::shared_ptr<const Indenter>> dataset_indenters(const Dataset& ds,
                                                                         const std::string& data_root,
                                                                         const std::string& split = "",
                                                                         Warnings* warnings = nullptr);
// Reads the calibration samples of `ds` (and nothing else). Throws InputError when it has none.
FitData load_calibration_data(const Dataset& ds, const std::string& data_root, Warnings* warnings = nullptr);

// FitSample from a loaded tsd sample.
FitSample to_fit_sample(const TsdSampleInfo& info, const SampleData& data, std::shared_ptr<const Indenter> indenter);

}  // namespace sb

namespace sb {

// The parameter file a fit writes: keyed by model id so `evaluate --params` reads it directly, plus a
// "_fit" object with the metadata (dataset, split, options, per model the stages with their losses,
// iterations and times):
//   {"hydroshear": {"lambda_d": ..., ...}, "_fit": {"dataset": ..., "split": "calibration", "models": {...}}}
nlohmann::json fit_file_json(const std::vector<CalibrationResult>& results, const Dataset& ds,
                             const FitOptions& options);

}  // namespace sb
