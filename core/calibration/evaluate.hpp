#pragma once
// The evaluation loop shared by `shearbench evaluate`, fits and the GUI: run a shear model over each
// sample's measured pose history and accumulate the field metrics (core/calibration/metrics.hpp) per motion type.
//
// Parameter files (--params P.json) are either keyed by model id,
//   {"hydroshear": {"mu": 0.4}, "fots": {"lambda": 30}}
// (an object whose values are all objects), or a flat table for the single model being run,
//   {"mu": 0.4}
// (an object whose values are all numbers). Keys a model does not know are errors (ParamSet).
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/calibration/metrics.hpp"
#include "core/data/tsd.hpp"
#include "core/models/model.hpp"

namespace sb {

// Makes the model that evaluates one sample (fresh state; the caller may reuse indenters across calls).
// Must be safe to call from several threads at once.
using ModelFactory = std::function<std::unique_ptr<ShearModel>(const TsdSampleInfo&)>;

// One scored frame's field (kept when asked: `evaluate --predictions`).
struct ScoredFrame {
  int frame = 0;
  std::vector<Vec2> pred_px, meas_px;  // per marker; NaN where the tracker lost a marker
};

struct SampleEvaluation {
  std::string sample_id;
  std::string motion;
  MetricsAccumulator metrics;
  std::vector<ScoredFrame> fields;  // empty unless keep_fields
};

struct EvaluationResult {
  std::string model_id;
  MotionMetrics metrics;                  // per motion and overall
  std::vector<SampleEvaluation> samples;  // in dataset order
  double seconds = 0;                     // wall time of the model runs and sample loads
};

// "calibration", "validation" or "all". Throws InputError(where) for anything else.
bool split_selected(const std::string& split_filter, const std::string& sample_split, const std::string& where);

// Resets `model`, steps it through every frame of `data` with dt_s, and adds each frame's predicted
// field against the measured markers to `acc`.
// Frames with nothing tracked (every marker NaN) are stepped without a field. fields (optional): every frame
// the metrics score, predicted and measured.
void run_sample(ShearModel& model, const SampleData& data, double dt_s, MetricsAccumulator* acc,
                std::vector<ScoredFrame>* fields = nullptr);

// Loads each selected sample lazily, evaluates it with a model from `factory` (in parallel over
// samples; results are merged in dataset order so they do not depend on the thread count).
EvaluationResult evaluate_dataset(const Dataset& ds, const ModelFactory& factory, const std::string& split_filter,
                                  const std::string& model_id, Warnings* warnings = nullptr, bool keep_fields = false);

// The kept fields as CSV rows sample,motion,frame,marker,meas_du_px,meas_dv_px,pred_du_px,pred_dv_px (a header
// line first): what a residual analysis outside shearbench reads.
std::string scored_fields_csv(const EvaluationResult& result);

// The parameter table for `model_id` from a params file (format above); an empty object when the file
// has none for it. `flat_allowed` is false when several models run (a flat table would be ambiguous).
nlohmann::json params_for_model(const nlohmann::json& params_file, const std::string& model_id, bool flat_allowed,
                                const std::string& where);

// A factory for the built-in models (make_model): builds each of the dataset's indenters once from its
// mesh (build_indenter, shape "mesh"), and applies `params` (one model's table) to every model.
ModelFactory dataset_model_factory(const Dataset& ds, const std::string& model_id, const nlohmann::json& params,
                                   const std::string& data_root, const std::string& params_where,
                                   Warnings* warnings = nullptr);

// JSON and Markdown reports. Markdown: the layout of the paper's calibration table, models as rows and
// the motion types as (RMSE, CS) column pairs, then the overall pair.
nlohmann::ordered_json evaluation_to_json(const std::vector<EvaluationResult>& results, const Dataset& ds,
                                          const std::string& split_filter);
std::string evaluation_to_markdown(const std::vector<EvaluationResult>& results, const std::string& title);

}  // namespace sb
