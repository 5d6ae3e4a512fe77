#include "core/calibration/rmse_series.hpp"

#include <cmath>
#include <limits>

#include "core/calibration/metrics.hpp"
#include "core/effects/model_spec.hpp"

namespace sb {

namespace {

double frame_rmse_or_nan(const std::vector<Vec2>& field, const std::vector<Vec2>& measured) {
  const MetricsResult m = frame_metrics(field, measured);
  return m.n > 0 ? m.rmse_px : std::numeric_limits<double>::quiet_NaN();
}

}  // namespace

std::vector<double> rmse_over_time(ShearModel& model, const std::vector<Pose>& path, double dt_s,
                                   const std::vector<std::vector<Vec2>>& measured_px, const std::atomic<bool>* cancel) {
  const std::size_t n = std::min(path.size(), measured_px.size());
  std::vector<double> series;
  series.reserve(n);
  model.reset();
  FieldOutput out;
  for (std::size_t k = 0; k < n; ++k) {
    if (cancel != nullptr && cancel->load(std::memory_order_relaxed)) break;
    model.step(path[k], dt_s, &out);
    series.push_back(frame_rmse_or_nan(out.disp_px, measured_px[k]));
  }
  return series;
}

std::vector<double> rmse_of_fields(const std::vector<std::vector<Vec2>>& fields,
                                   const std::vector<std::vector<Vec2>>& measured_px) {
  const std::size_t n = std::min(fields.size(), measured_px.size());
  std::vector<double> series(n);
  for (std::size_t k = 0; k < n; ++k) series[k] = frame_rmse_or_nan(fields[k], measured_px[k]);
  return series;
}

RmseSeriesJob::~RmseSeriesJob() { stop(); }

void RmseSeriesJob::stop() {
  cancel_ = true;
  if (worker_.joinable()) worker_.join();
  cancel_ = false;
}

void RmseSeriesJob::start(RmseSeriesRequest request) {
  stop();
  const std::uint64_t generation = ++generation_;
  running_ = true;
  worker_ = std::thread([this, generation, req = std::move(request)] {
    std::vector<std::vector<double>> series;
    try {
      for (std::size_t m = 0; m < req.model_ids.size() && !cancel_; ++m) {
        auto model = make_spec_model(req.model_ids[m], req.sensor, req.indenter);
        model->set_params(req.params.at(m));
        series.push_back(rmse_over_time(*model, req.path, req.dt_s, req.measured_px, &cancel_));
      }
    } catch (const std::exception&) {
      series.clear();  // a pose the model refuses: no plot rather than a wrong one
    }
    if (!cancel_) {
      std::lock_guard<std::mutex> lock(mutex_);
      result_ = std::move(series);
      result_generation_ = generation;
    }
    running_ = false;
  });
}

std::vector<std::vector<double>> RmseSeriesJob::result(std::uint64_t* generation) const {
  std::lock_guard<std::mutex> lock(mutex_);
  if (generation) *generation = result_generation_;
  return result_;
}

}  // namespace sb
