// How the measured and a model's fields respond to the known inputs (input_response.hpp).
#include "core/loop/input_response.hpp"
#include "core/base/median.hpp"

#include <tbb/parallel_for.h>

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <set>
#include <sstream>
#include <stdexcept>

#include "core/base/format.hpp"
#include "core/effects/effects.hpp"
#include "core/effects/model_spec.hpp"
#include "core/loop/loop_samples.hpp"

namespace sb {

std::array<double, kPoseInputCount> as_array(const PoseInputs& x) {
  return {x.depth_m, x.tilt.x(), x.tilt.y(), x.travel_m.x(), x.travel_m.y(), x.twist_rad};
}

const std::array<const char*, kPoseInputCount>& pose_input_names() {
  static const std::array<const char*, kPoseInputCount> names = {"depth",    "tilt x",   "tilt y",
                                                                 "travel x", "travel y", "twist"};
  return names;
}

namespace {

// Rotation about E's z of R (exact for a rotation about z; the z part of a general one).
double twist_about_z(const Eigen::Matrix3d& R) { return std::atan2(R(1, 0) - R(0, 1), R(0, 0) + R(1, 1)); }

PoseInputs with_input(PoseInputs x, int i, double value) {
  switch (i) {
    case 0: x.depth_m = value; break;
    case 1: x.tilt.x() = value; break;
    case 2: x.tilt.y() = value; break;
    case 3: x.travel_m.x() = value; break;
    case 4: x.travel_m.y() = value; break;
    default: x.twist_rad = value; break;
  }
  return x;
}

// Singular value, relative to the largest, below which a direction of a response surface's terms counts as not
// determined by the frames (features scaled by their spread: O(1) for what the frames determine).
constexpr double kRankTolerance = 1e-4;

// Below these spreads over the fitted frames an input counts as held (its terms left out): 1 um of depth or
// travel, 1e-4 of tilt (sin) or twist (rad), under what a pose log resolves; scaled by a spread that small,
// rounding noise would become a feature of size one.
constexpr std::array<double, kPoseInputCount> kInputResolution = {1e-6, 1e-4, 1e-4, 1e-6, 1e-6, 1e-4};

// Frames a response surface needs per term: with fewer, its degree is lowered (to 1 at least). The twins'
// few calibration samples (137 frames) gave a cubic of four inputs 35 terms, ~4 frames each: it followed the
// frames, and on validation frames inside their range it scored 1.80 px where a linear function scores 1.72.
constexpr double kFramesPerTerm = 10.0;

// Every exponent tuple of the inputs that vary with total degree 1..degree, and the constant.
std::vector<std::array<int, kPoseInputCount>> monomials(const std::array<bool, kPoseInputCount>& varies, int degree) {
  std::vector<std::array<int, kPoseInputCount>> out{{}};
  for (int d = 1; d <= degree; ++d) {
    std::vector<std::array<int, kPoseInputCount>> next;
    for (const auto& e : out) {
      int total = 0;
      for (int v : e) total += v;
      if (total != d - 1) continue;
      // Raise one input at or after the last raised one, so each tuple is generated once.
      int last = 0;
      for (int i = 0; i < kPoseInputCount; ++i)
        if (e[i] > 0) last = i;
      for (int i = last; i < kPoseInputCount; ++i) {
        if (!varies[i]) continue;
        auto f = e;
        ++f[i];
        next.push_back(f);
      }
    }
    out.insert(out.end(), next.begin(), next.end());
  }
  return out;
}

struct FieldStats {
  double rms_a = 0, rms_b = 0, gain = 0, after_gain = 0;
  Vec2 mean_a{0, 0}, mean_b{0, 0};
};

// a = measured, b = model, over the markers finite in both.
FieldStats compare(const std::vector<Vec2>& a, const std::vector<Vec2>& b) {
  FieldStats s;
  double aa = 0, bb = 0, ab = 0;
  long n = 0;
  for (std::size_t m = 0; m < a.size(); ++m) {
    if (!a[m].allFinite() || !b[m].allFinite()) continue;
    aa += a[m].squaredNorm(), bb += b[m].squaredNorm(), ab += a[m].dot(b[m]);
    s.mean_a += a[m], s.mean_b += b[m];
    ++n;
  }
  if (n == 0) return s;
  s.rms_a = std::sqrt(aa / n), s.rms_b = std::sqrt(bb / n);
  s.mean_a /= double(n), s.mean_b /= double(n);
  s.gain = bb > 0 ? ab / bb : 0.0;
  s.after_gain = std::sqrt(std::max(0.0, aa - 2 * s.gain * ab + s.gain * s.gain * bb) / n);
  return s;
}

std::vector<Vec2> minus(const std::vector<Vec2>& a, const std::vector<Vec2>& b) {
  std::vector<Vec2> out(a.size());
  for (std::size_t m = 0; m < a.size(); ++m) out[m] = a[m] - b[m];
  return out;
}

// "depth +1.2 mm", "tilt x +9.6 deg", "travel y +2.1 mm", "twist +2.9 deg".
std::string step_label(int i, double step) {
  const bool angle = i == 1 || i == 2;
  const double shown = i == 0 || i == 3 || i == 4 ? step * 1e3
                       : angle                    ? std::asin(std::clamp(step, -1.0, 1.0)) * 180.0 / std::numbers::pi
                                                  : step * 180.0 / std::numbers::pi;
  const char* unit = i == 0 || i == 3 || i == 4 ? " mm" : " deg";
  return std::string(pose_input_names()[i]) + " " + format_number(shown, "%+.2g") + unit;
}

InputResponse response_row(std::string label, const std::vector<Vec2>& measured, const std::vector<Vec2>& model) {
  const FieldStats s = compare(measured, model);
  return {std::move(label), s.rms_a, s.rms_b, s.gain, s.after_gain, s.mean_a, s.mean_b};
}

}  // namespace

std::vector<PoseInputs> pose_inputs(const Sdf& gel_sdf_E, const Indenter& indenter, const std::vector<Pose>& X_EI) {
  if (X_EI.empty()) throw std::invalid_argument("pose_inputs: no poses");
  std::vector<PoseInputs> out(X_EI.size());
  int first_contact = -1;
  for (std::size_t k = 0; k < X_EI.size(); ++k) {
    const Penetration pen = indenter_penetration(gel_sdf_E, indenter, X_EI[k]);
    PoseInputs& x = out[k];
    x.depth_m = pen.depth_m;
    x.tilt = (X_EI[k].linear() * Vec3::UnitZ()).head<2>();
    if (pen.penetrating && first_contact < 0) first_contact = static_cast<int>(k);
    if (first_contact < 0) continue;
    const Pose& X0 = X_EI[static_cast<std::size_t>(first_contact)];
    x.travel_m = (X_EI[k].translation() - X0.translation()).head<2>();
    x.twist_rad = twist_about_z(X_EI[k].linear() * X0.linear().transpose());
  }
  return out;
}

ResponseSurface ResponseSurface::fit(const std::vector<PoseInputs>& inputs,
                                     const std::vector<std::vector<Vec2>>& fields, int degree) {
  if (inputs.size() != fields.size() || inputs.empty())
    throw std::invalid_argument("ResponseSurface: " + std::to_string(inputs.size()) + " input rows for " +
                                std::to_string(fields.size()) + " fields");
  if (degree < 1 || degree > 3) throw std::invalid_argument("ResponseSurface: degree must be 1..3");
  ResponseSurface s;
  std::array<bool, kPoseInputCount> varies{};
  for (int i = 0; i < kPoseInputCount; ++i) {
    double sum = 0, sq = 0;
    for (const auto& x : inputs) sum += as_array(x)[i], sq += as_array(x)[i] * as_array(x)[i];
    const double n = double(inputs.size()), mean = sum / n, var = std::max(0.0, sq / n - mean * mean);
    s.centre_[i] = mean;
    const auto [lo, hi] = std::minmax_element(
        inputs.begin(), inputs.end(), [i](const auto& a, const auto& b) { return as_array(a)[i] < as_array(b)[i]; });
    s.lo_[i] = as_array(*lo)[i], s.hi_[i] = as_array(*hi)[i];
    varies[i] = std::sqrt(var) > kInputResolution[i];
    s.spread_[i] = varies[i] ? std::sqrt(var) : 1.0;
  }
  s.varies_ = varies;
  int used = degree;
  while (used > 1 && double(inputs.size()) < kFramesPerTerm * double(monomials(varies, used).size())) --used;
  s.degree_ = used;
  s.exponents_ = monomials(varies, used);
  const std::size_t markers = fields.front().size(), terms = s.exponents_.size();
  Eigen::MatrixXd all(inputs.size(), terms);
  for (std::size_t f = 0; f < inputs.size(); ++f) {
    if (fields[f].size() != markers) throw std::invalid_argument("ResponseSurface: frames differ in marker count");
    const auto row = s.features(inputs[f]);
    for (std::size_t t = 0; t < terms; ++t) all(f, t) = row[t];
  }
  s.coef_u_.resize(markers), s.coef_v_.resize(markers);
  tbb::parallel_for(std::size_t{0}, markers, [&](std::size_t m) {
    std::vector<int> rows;
    for (std::size_t f = 0; f < inputs.size(); ++f)
      if (fields[f][m].allFinite()) rows.push_back(static_cast<int>(f));
    if (rows.size() < terms) return;
    Eigen::MatrixXd A(rows.size(), terms);
    Eigen::MatrixXd b(rows.size(), 2);
    for (std::size_t r = 0; r < rows.size(); ++r) {
      A.row(r) = all.row(rows[r]);
      b.row(r) = fields[static_cast<std::size_t>(rows[r])][m].transpose();
    }
    // The minimum-norm least-squares solution, directions the frames hardly determine left out: a pivoted QR's
    // basic solution gave terms the frames hardly tell apart (the twins' slide travel and twist) huge
    // coefficients that cancel on the frames and nowhere else (validation predicted to 1e11 px).
    Eigen::BDCSVD<Eigen::MatrixXd> svd(A, Eigen::ComputeThinU | Eigen::ComputeThinV);
    svd.setThreshold(kRankTolerance);
    const Eigen::MatrixXd c = svd.solve(b);
    s.coef_u_[m].assign(c.col(0).data(), c.col(0).data() + terms);
    s.coef_v_[m].assign(c.col(1).data(), c.col(1).data() + terms);
  });
  return s;
}

std::vector<double> ResponseSurface::features(const PoseInputs& x) const {
  std::array<double, kPoseInputCount> z = as_array(x);
  for (int i = 0; i < kPoseInputCount; ++i) z[i] = (z[i] - centre_[i]) / spread_[i];
  std::vector<double> out(exponents_.size(), 1.0);
  for (std::size_t t = 0; t < exponents_.size(); ++t)
    for (int i = 0; i < kPoseInputCount; ++i)
      for (int p = 0; p < exponents_[t][i]; ++p) out[t] *= z[i];
  return out;
}

bool ResponseSurface::within_range(const PoseInputs& x) const {
  const auto v = as_array(x);
  for (int i = 0; i < kPoseInputCount; ++i)
    if (v[i] < lo_[i] || v[i] > hi_[i]) return false;
  return true;
}

std::vector<Vec2> ResponseSurface::predict(const PoseInputs& x) const {
  const auto f = features(x);
  std::vector<Vec2> out(coef_u_.size(), Vec2::Constant(std::numeric_limits<double>::quiet_NaN()));
  for (std::size_t m = 0; m < coef_u_.size(); ++m) {
    if (coef_u_[m].empty()) continue;
    Vec2 d(0, 0);
    for (std::size_t t = 0; t < f.size(); ++t) d += f[t] * Vec2(coef_u_[m][t], coef_v_[m][t]);
    out[m] = d;
  }
  return out;
}

InputResponseAnalysis analyse_input_response(const std::vector<ScoredInputFrame>& calibration,
                                             const std::vector<ScoredInputFrame>& validation, int degree) {
  if (calibration.empty() || validation.empty())
    throw std::invalid_argument("input response: no scored frames in the calibration or validation split");
  std::vector<PoseInputs> x;
  std::vector<std::vector<Vec2>> meas, model;
  for (const auto& f : calibration) x.push_back(f.inputs), meas.push_back(f.measured_px), model.push_back(f.model_px);
  const ResponseSurface S_meas = ResponseSurface::fit(x, meas, degree);
  const ResponseSurface S_model = ResponseSurface::fit(x, model, degree);

  InputResponseAnalysis a;
  a.degree_asked = degree;
  a.degree = S_meas.degree();
  std::array<double, kPoseInputCount> step{};
  for (int i = 0; i < kPoseInputCount; ++i) {
    step[i] = S_meas.spread(i);
    double ref = 0.0;
    if (i == 0 || S_meas.lo(i) > 0.0 || S_meas.hi(i) < 0.0) {
      std::vector<double> v;
      v.reserve(x.size());
      for (const auto& xi : x) v.push_back(as_array(xi)[i]);
      ref = median(v);
    }
    a.reference = with_input(a.reference, i, ref);
  }
  const auto m0 = S_meas.predict(a.reference), p0 = S_model.predict(a.reference);
  a.responses.push_back(response_row("at the reference", m0, p0));
  for (int i = 0; i < kPoseInputCount; ++i) {
    if (step[i] == 0.0) continue;  // held in every calibration frame
    const PoseInputs xi = with_input(a.reference, i, as_array(a.reference)[i] + step[i]);
    a.responses.push_back(
        response_row(step_label(i, step[i]), minus(S_meas.predict(xi), m0), minus(S_model.predict(xi), p0)));
  }

  double sse_inputs = 0, sse_model = 0;
  for (const auto& f : validation) {
    ++a.validation_frames;
    if (!S_meas.within_range(f.inputs)) {  // a polynomial says nothing there: not scored
      ++a.validation_frames_outside;
      continue;
    }
    const auto pred = S_meas.predict(f.inputs);
    for (std::size_t m = 0; m < f.measured_px.size(); ++m) {
      if (!f.measured_px[m].allFinite() || !pred[m].allFinite() || !f.model_px[m].allFinite()) continue;
      sse_inputs += (f.measured_px[m] - pred[m]).squaredNorm();
      sse_model += (f.measured_px[m] - f.model_px[m]).squaredNorm();
      ++a.validation_marker_frames;
    }
  }
  if (a.validation_marker_frames > 0) {
    a.inputs_only_rmse_px = std::sqrt(sse_inputs / double(a.validation_marker_frames));
    a.model_rmse_px = std::sqrt(sse_model / double(a.validation_marker_frames));
  }
  return a;
}

std::vector<ScoredInputFrame> scored_input_frames(const std::string& model_id, const ParamSet& params,
                                                  std::shared_ptr<const Sensor> sensor,
                                                  const std::vector<FitSample>& samples) {
  std::vector<std::vector<ScoredInputFrame>> per_sample(samples.size());
  tbb::parallel_for(std::size_t{0}, samples.size(), [&](std::size_t i) {
    const FitSample& s = samples[i];
    if (s.X_EI.empty()) return;
    const std::size_t markers = s.meas_px.front().size();
    std::set<std::size_t> scored;
    for (int flat : active_marker_frames(s.meas_px)) scored.insert(static_cast<std::size_t>(flat) / markers);
    if (scored.empty()) return;
    const auto inputs = pose_inputs(*sensor->gel_sdf, *s.indenter, s.X_EI);
    auto model = make_spec_model(model_id, sensor, s.indenter);
    ParamSet p = model->params();
    copy_shared(params, &p);
    model->set_params(p);
    model->reset();
    FieldOutput out;
    for (std::size_t k = 0; k < s.X_EI.size(); ++k) {
      const bool wanted = scored.count(k) > 0;
      model->step(s.X_EI[k], k == 0 ? 0.0 : s.dt_s, wanted ? &out : nullptr);
      if (wanted) per_sample[i].push_back({inputs[k], s.meas_px[k], out.disp_px});
    }
  });
  std::vector<ScoredInputFrame> all;
  for (auto& v : per_sample)
    all.insert(all.end(), std::make_move_iterator(v.begin()), std::make_move_iterator(v.end()));
  return all;
}

std::string input_response_markdown(const InputResponseAnalysis& a, const std::string& model_id) {
  std::ostringstream md;
  const auto f = [](double v, const char* fmt = "%.2f") { return format_number(v, fmt); };
  const auto vec = [&](const Vec2& v) { return "(" + f(v.x()) + ", " + f(v.y()) + ")"; };
  static const char* const kDegreeNames[] = {"", "linear function", "quadratic", "cubic"};
  md << "Each field regressed per marker on a " << kDegreeNames[std::clamp(a.degree, 0, 3)]
     << " of the frame's inputs (depth, tilt, travel since first contact, twist; from the poses), fitted on "
        "calibration"
     << (a.degree < a.degree_asked ? " (lowered: fewer than ten calibration frames per term)" : "")
     << ". Reference: depth " << f(a.reference.depth_m * 1e3) << " mm, the other inputs " << vec(a.reference.tilt)
     << ", " << vec(a.reference.travel_m * 1e3) << " mm, " << f(a.reference.twist_rad * 180.0 / std::numbers::pi)
     << " deg; each row changes one input by its standard deviation.\n\n"
     << "| change | measured RMS px | " << model_id << " RMS px | best gain | shape error after gain px | "
     << "mean measured px | mean model px |\n|---|---:|---:|---:|---:|---|---|\n";
  for (const auto& r : a.responses)
    md << "| " << r.input << " | " << f(r.measured_rms_px) << " | " << f(r.model_rms_px) << " | " << f(r.gain) << " | "
       << f(r.after_gain_rms_px) << " | " << vec(r.measured_mean_px) << " | " << vec(r.model_mean_px) << " |\n";
  md << "\nThe inputs alone (the measured surface, fitted on calibration) predict validation to "
     << f(a.inputs_only_rmse_px, "%.3f") << " px";
  if (a.validation_frames_outside > 0)
    md << " on its " << a.validation_frames - a.validation_frames_outside << " of " << a.validation_frames
       << " frames whose inputs lie inside the calibration frames' range (a polynomial says nothing outside it)";
  md << "; " << model_id << " on the same " << a.validation_marker_frames
     << " marker-frames: " << f(a.model_rmse_px, "%.3f") << " px.\n";
  return md.str();
}

}  // namespace sb
