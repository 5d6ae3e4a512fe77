// Samples as the residual loop's steps see them (loop_samples.hpp).
#include "core/loop/loop_samples.hpp"

#include <tbb/parallel_for.h>

#include <Eigen/Geometry>
#include <stdexcept>

#include "core/effects/effects.hpp"
#include "core/effects/model_spec.hpp"

namespace sb {

bool held_still(const Pose& before, const Pose& after) {
  const double moved_m = (after.translation() - before.translation()).norm();
  const double turned_rad = Eigen::AngleAxisd(before.linear().transpose() * after.linear()).angle();
  return moved_m < kHeldStillM && turned_rad < kHeldStillRad;
}

SampleModelFactory spec_model_factory(const std::string& model_id, const std::shared_ptr<const Sensor>& sensor) {
  return [model_id, sensor](const FitSample& s, std::size_t) { return make_spec_model(model_id, sensor, s.indenter); };
}

FitModelFactory spec_fit_factory(const std::string& model_id, const std::shared_ptr<const Sensor>& sensor) {
  return [model_id, sensor](std::shared_ptr<const Indenter> ind) {
    return make_spec_model(model_id, sensor, std::move(ind));
  };
}

namespace {

// Held-drift sums of one sample (FitResult::held_*).
struct HeldDrift {
  double sse = 0, signal = 0, count = 0;
};

// Over every run of frames in which the indenter is in the gel and held still, the change of the field since
// the run's first frame, measured against predicted, on the markers that moved >= kActiveFramePx when the
// hold began: creep is proportional to the field, the other markers hold only noise.
HeldDrift held_drift(const Sensor& sensor, const FitSample& s, const std::vector<std::vector<Vec2>>& pred) {
  HeldDrift h;
  std::size_t start = 0;
  bool in_run = false;
  for (std::size_t k = 1; k < s.X_EI.size(); ++k) {
    if (!held_still(s.X_EI[k - 1], s.X_EI[k])) {
      in_run = false;
      continue;
    }
    if (!in_run) {
      if (!indenter_penetration(*sensor.gel_sdf, *s.indenter, s.X_EI[k]).penetrating) continue;
      in_run = true;
      start = k - 1;
    }
    for (std::size_t j = 0; j < s.meas_px[k].size(); ++j) {
      const Vec2 dm = s.meas_px[k][j] - s.meas_px[start][j];
      if (!dm.allFinite() || !(s.meas_px[start][j].norm() >= kActiveFramePx)) continue;
      h.sse += (dm - (pred[k][j] - pred[start][j])).squaredNorm();
      h.signal += dm.squaredNorm();
      h.count += 1;
    }
  }
  return h;
}

// Replays a recorded field (per frame: the displacement and the contact flags). set_params ignores the
// form's parameters: the field was recorded with fixed ones.
class ReplayModel final : public ShearModel {
 public:
  ReplayModel(std::string id, ParamSet params, RecordedField frames)
      : id_(std::move(id)), params_(std::move(params)), frames_(std::move(frames)) {}
  std::string id() const override { return id_; }
  const ParamSet& params() const override { return params_; }
  void set_params(const ParamSet&) override {}
  void reset() override { next_ = 0; }
  void step(const Pose&, double, FieldOutput* out) override {
    if (next_ >= frames_->size()) throw std::logic_error("ReplayModel: stepped past the recorded frames");
    const FieldOutput& f = (*frames_)[next_++];
    if (out == nullptr) return;
    out->disp_px = f.disp_px;
    out->marker_in_contact = f.marker_in_contact;
  }
  std::unique_ptr<ShearModel> clone() const override { return std::make_unique<ReplayModel>(*this); }

 private:
  std::string id_;
  ParamSet params_;
  RecordedField frames_;
  std::size_t next_ = 0;
};

}  // namespace

SplitScores score_samples(const SampleModelFactory& make, const ParamSet& params, const Sensor& sensor,
                          const std::vector<FitSample>& samples) {
  SplitScores sc;
  sc.sse.assign(samples.size(), 0.0);
  sc.count.assign(samples.size(), 0.0);
  std::vector<HeldDrift> held(samples.size());
  std::vector<MetricsAccumulator> acc(samples.size());
  tbb::parallel_for(0, static_cast<int>(samples.size()), [&](int i) {
    auto model = make(samples[i], static_cast<std::size_t>(i));
    model->set_params(params);
    const auto pred = simulate_sample(*model, samples[i]);
    const std::size_t m = samples[i].meas_px.front().size();
    for (int f : active_marker_frames(samples[i].meas_px)) {
      sc.sse[i] += (pred[f / m][f % m] - samples[i].meas_px[f / m][f % m]).squaredNorm();
      sc.count[i] += 1;
    }
    for (std::size_t k = 0; k < pred.size(); ++k) acc[i].add_frame(pred[k], samples[i].meas_px[k]);
    held[i] = held_drift(sensor, samples[i], pred);
  });
  for (std::size_t i = 0; i < samples.size(); ++i) {
    sc.metrics.add(samples[i].motion, acc[i]);
    sc.held_sse += held[i].sse;
    sc.held_signal += held[i].signal;
    sc.held_count += held[i].count;
  }
  return sc;
}

std::vector<RecordedField> record_field(const std::string& model_id, const ParamSet& params,
                                        std::shared_ptr<const Sensor> sensor, const std::vector<FitSample>& samples) {
  std::vector<RecordedField> out(samples.size());
  tbb::parallel_for(0, static_cast<int>(samples.size()), [&](int i) {
    auto model = make_spec_model(model_id, sensor, samples[i].indenter);
    ParamSet p = model->params();
    copy_shared(params, &p);
    model->set_params(p);
    model->reset();
    auto frames = std::make_shared<std::vector<FieldOutput>>(samples[i].X_EI.size());
    for (std::size_t k = 0; k < samples[i].X_EI.size(); ++k) {
      FieldOutput& f = (*frames)[k];
      model->step(samples[i].X_EI[k], k == 0 ? 0.0 : samples[i].dt_s, &f);
      // Only the field is replayed: the tracked points' storage goes, capacity included (clear() keeps it, and
      // on the TacTip it was most of a recording's memory).
      std::vector<Vec3>().swap(f.p_EP);
      std::vector<Vec3>().swap(f.anchor_EP);
      std::vector<PointState>().swap(f.point_state);
      f.disp_px.shrink_to_fit();
      f.marker_in_contact.shrink_to_fit();
    }
    out[i] = std::move(frames);
  });
  return out;
}

SampleModelFactory replay_factory(const std::string& form_id, const std::vector<std::string>& effect_ids,
                                  const ParamSet& form_params, const std::vector<RecordedField>* recorded,
                                  const std::shared_ptr<const Sensor>& sensor) {
  ParamSet own = model_spec_params(form_id);  // the form's own table (EffectModel splits the combined one by it)
  copy_shared(form_params, &own);
  return
      [form_id, effect_ids, own, recorded, sensor](const FitSample& s, std::size_t i) -> std::unique_ptr<ShearModel> {
        auto replay = std::make_unique<ReplayModel>(form_id, own, recorded->at(i));
        return wrap_with_effects(std::move(replay), effect_ids, sensor, s.indenter);
      };
}

std::vector<FingerprintSample> fingerprint_samples(const Sensor& sensor, const std::vector<FitSample>& samples) {
  std::vector<FingerprintSample> out(samples.size());
  tbb::parallel_for(0, static_cast<int>(samples.size()), [&](int i) {
    const FitSample& s = samples[i];
    FingerprintSample& f = out[i];
    f.dt_s = s.dt_s;
    f.meas_px = s.meas_px;
    bool touched = false;
    Vec2 first_px = Vec2::Zero();
    for (std::size_t k = 0; k < s.X_EI.size(); ++k) {
      const Penetration pen = indenter_penetration(*sensor.gel_sdf, *s.indenter, s.X_EI[k]);
      const Vec2 centre_px = sensor.camera.px_from_E(pen.centre_E);
      if (pen.penetrating && !touched) first_px = centre_px, touched = true;
      f.in_contact.push_back(pen.penetrating);
      f.held.push_back(pen.penetrating && k > 0 && held_still(s.X_EI[k - 1], s.X_EI[k]));
      f.contact_centre_px.push_back(centre_px);
      f.travel_px.push_back(touched ? (centre_px - first_px).norm() : 0.0);
    }
  });
  return out;
}

ModelFieldScope::ModelFieldScope(std::vector<FingerprintSample>* fs, const SampleModelFactory& make,
                                 const ParamSet& params, const std::vector<FitSample>& samples)
    : fs_(fs) {
  tbb::parallel_for(0, static_cast<int>(samples.size()), [&](int i) {
    auto model = make(samples[i], static_cast<std::size_t>(i));
    model->set_params(params);
    (*fs_)[i].pred_px = simulate_sample(*model, samples[i]);
  });
}

ModelFieldScope::~ModelFieldScope() {
  for (FingerprintSample& f : *fs_) std::vector<std::vector<Vec2>>().swap(f.pred_px);
}

void throw_if_cancelled(const CalibrationResult& r, const Progress& progress) {
  if (r.cancelled || progress.cancelled()) throw Cancelled("residual analysis");
}

std::vector<std::size_t> evenly_spaced(std::size_t count, std::size_t n) {
  if (n == 0 || n > count) n = count;
  std::vector<std::size_t> out(n);
  for (std::size_t i = 0; i < n; ++i) out[i] = i * count / n;
  return out;
}

std::vector<FitSample> subset(const std::vector<FitSample>& samples, const std::vector<std::size_t>& indices) {
  std::vector<FitSample> out;
  out.reserve(indices.size());
  for (std::size_t i : indices) out.push_back(samples.at(i));
  return out;
}

void copy_shared(const ParamSet& from, ParamSet* to) {
  for (std::size_t i = 0; i < to->size(); ++i) {
    const int j = from.index_of(to->specs()[i].name);
    if (j >= 0) to->set(i, from[static_cast<std::size_t>(j)]);
  }
}

}  // namespace sb
