// The residual loop on data with an undeclared effect: simulate fots-reimpl + one catalogued effect at
// non-default parameters plus Gaussian tracking noise, hand the data to the loop without naming the
// effect, and check it selects that effect, recovers its parameters and lowers the validation RMSE.
#include <catch2/catch.hpp>

#include "temp_path.hpp"
#include "test_poses.hpp"

#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <tuple>

#include "core/effects/effects.hpp"
#include "core/loop/residual.hpp"
#include "core/loop/residual_report.hpp"
#include "core/loop/rest_grid_lens.hpp"

// This file's names in a namespace of its own: the unity build (CMAKE_UNITY_BUILD) compiles several
// test files as one translation unit.
namespace test_residual {

using sb::FitSample;
using sb::Pose;
using sb::Vec2;
using sb::Vec3;
using sbtest::sphere4mm_pose;

namespace {

// Tracker noise of the brief: 0.05 px per component (real GelSight Mini trackers: 0.03-0.1 px).
constexpr double kNoisePx = 0.05;
// Recovered effect parameters must lie within 15 % of the injected values.
constexpr double kParamRelTol = 0.15;
// The base model the data come from, with its default parameters held fixed (the loop gets them as --params
// would give them): the test is about attribution, not about the base calibration.
const std::string kBase = "fots-reimpl";
constexpr double kDt = 0.05;  // s; 30 frames = 1.5 s per sample

struct Setup {
  std::shared_ptr<const sb::Sensor> sensor = std::make_shared<const sb::Sensor>(sb::make_default_sensor());
  std::shared_ptr<const sb::Indenter> sphere;
  Setup() {
    sb::IndenterSpec spec;
    spec.shape = "sphere";
    spec.radius_m = 0.004;
    sphere = std::make_shared<const sb::Indenter>(sb::build_indenter(spec, "", ""));
  }
};

const Setup& setup() {
  static const Setup s;
  return s;
}

// A press in 8 frames, a 16-frame hold (sliding `slide` and turning `yaw_deg` over it), a release in 6.
FitSample press(const std::string& id, const std::string& motion, const std::string& split, Vec2 at, double depth,
                Vec2 slide, double yaw_deg) {
  FitSample s;
  s.id = id;
  s.motion = motion;
  s.split = split;
  s.dt_s = kDt;
  s.indenter = setup().sphere;
  for (int k = 0; k < 8; ++k) s.X_EI.push_back(sphere4mm_pose(at.x(), at.y(), depth * (k + 1) / 8.0, 0));
  for (int k = 1; k <= 16; ++k) {
    const Vec2 p = at + slide * std::min(1.0, k / 10.0);
    s.X_EI.push_back(sphere4mm_pose(p.x(), p.y(), depth, yaw_deg * std::min(1.0, k / 10.0)));
  }
  const Vec2 end = at + slide;
  for (int k = 1; k <= 6; ++k)
    s.X_EI.push_back(sphere4mm_pose(end.x(), end.y(), depth * (1 - k / 5.0), yaw_deg));  // last frame lifted off
  return s;
}

std::vector<FitSample> trajectories(const std::string& split) {
  const bool cal = split == "calibration";
  const double o = cal ? 1.0 : -1.0;  // validation presses mirror the calibration ones
  return {press(split + "_dil", "dilation", split, Vec2(-2e-3 * o, 1e-3), 1.0e-3, Vec2::Zero(), 0),
          press(split + "_dil2", "dilation", split, Vec2(3e-3 * o, -2e-3 * o), 1.4e-3, Vec2::Zero(), 0),
          press(split + "_shr", "shear", split, Vec2(1e-3 * o, 0.5e-3), 1.0e-3, Vec2(0.5e-3 * o, 0.2e-3), 0),
          press(split + "_twi", "twist", split, Vec2(0, -1e-3 * o), 1.2e-3, Vec2::Zero(), 12 * o)};
}

// Effects with their true parameters (own names), in the order they wrap the base.
using Truths = std::vector<std::pair<std::string, std::map<std::string, double>>>;

// Simulates base + `effects` at their truths with tracker noise.
void simulate(std::vector<FitSample>* samples, const Truths& effects, const std::shared_ptr<const sb::Sensor>& sensor,
              std::uint64_t seed, const std::string& base = kBase, const sb::ParamSet* base_params = nullptr) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, kNoisePx);
  for (auto& s : *samples) {
    std::vector<std::string> ids;
    for (const auto& e : effects) ids.push_back(e.first);
    auto model = sb::wrap_with_effects(sb::make_model(base, sensor, s.indenter), ids, sensor, s.indenter);
    sb::ParamSet p = model->params();
    if (base_params != nullptr)
      for (const auto& spec : base_params->specs()) p.set(spec.name, base_params->get(spec.name));
    for (const auto& [effect, truth] : effects)
      for (const auto& [name, value] : truth) p.set(effect + "." + name, value);
    model->set_params(p);
    s.meas_px = sb::simulate_sample(*model, s);
    for (auto& frame : s.meas_px)
      for (auto& d : frame) {
        const double dx = noise(rng);  // sequenced: argument order is unspecified
        d += Vec2(dx, noise(rng));
      }
  }
}

// Simulates base + `effect` at `truth` (or the base alone when effect is empty) with tracker noise.
void simulate(std::vector<FitSample>* samples, const std::string& effect, const std::map<std::string, double>& truth,
              const std::shared_ptr<const sb::Sensor>& sensor, std::uint64_t seed) {
  simulate(samples, effect.empty() ? Truths{} : Truths{{effect, truth}}, sensor, seed);
}

// The sensor the data are recorded with: a lens also bends the rest grid it images (the markers stay where
// they are: p_EM kept), which is the lens's fingerprint (core/loop/rest_grid_lens.hpp).
std::shared_ptr<const sb::Sensor> recording_sensor(const std::string& effect,
                                                   const std::map<std::string, double>& truth) {
  if (effect != "lens_distortion") return setup().sensor;
  auto bent = std::make_shared<sb::Sensor>(*setup().sensor);
  for (Vec2& m : bent->markers_rest_px) m = sb::lens_distort_px(bent->camera, truth.at("k1"), m);
  return bent;
}

sb::ResidualReport run_loop(const std::string& effect, const std::map<std::string, double>& truth) {
  sb::ResidualInputs in;
  in.dataset = "synthetic:" + (effect.empty() ? std::string("none") : effect);
  in.model_id = kBase;
  in.sensor = recording_sensor(effect, truth);
  in.base_params = sb::default_params(kBase);
  in.calibration = trajectories("calibration");
  in.validation = trajectories("validation");
  simulate(&in.calibration, effect, truth, in.sensor, 11);
  simulate(&in.validation, effect, truth, in.sensor, 23);
  sb::ResidualOptions o;
  o.max_iterations = 15;  // bounds the test time; the recovery checks below fail if it were too few
  o.fit_base = false;     // every catalogued effect is a candidate: the loop is not told which one is in the data
  return sb::run_residual_loop(in, o);
}

void check_recovers(const std::string& effect, const std::map<std::string, double>& truth) {
  const auto r = run_loop(effect, truth);
  const auto j = sb::residual_to_json(r);
  INFO(j["candidates"].dump(1));
  REQUIRE(r.effects.selection.selected.size() >= 1);
  CHECK(r.effects.selection.selected.front() == effect);
  REQUIRE(r.effects.selection.selected.size() == 1);  // the second greedy round finds nothing left to explain
  for (const auto& [name, value] : truth) {
    const double fitted = r.after.fit.params.get(effect + "." + name);
    INFO(effect << "." << name << ": fitted " << fitted << ", injected " << value);
    CHECK(std::abs(fitted - value) <= kParamRelTol * std::abs(value));
  }
  const double before = r.before.validation.overall.result().rmse_px;
  const double after = r.after.validation.overall.result().rmse_px;
  INFO("validation RMSE " << before << " -> " << after << " px");
  CHECK(after < before);
  // With the effect explained only the tracker noise is left: RMSE of a 2-D Gaussian of sigma per
  // component is sqrt(2) sigma = 0.0707 px; allow 30 % for fitting error.
  CHECK(after < 1.3 * std::sqrt(2.0) * kNoisePx);
}

}  // namespace

TEST_CASE("residual loop attributes undeclared viscoelastic creep", "[residual][slow]") {
  check_recovers("viscoelastic_creep", {{"tau_s", 0.4}, {"creep_fraction", 0.3}});
}

TEST_CASE("residual loop attributes undeclared lens distortion", "[residual][slow]") {
  check_recovers("lens_distortion", {{"k1", 0.3}});
}

TEST_CASE("residual loop attributes undeclared tracker bias", "[residual][slow]") {
  check_recovers("tracker_bias", {{"gain", 1.1}, {"bias_x_px", 0.6}, {"bias_y_px", -0.4}});
}

TEST_CASE("residual loop attributes undeclared subsurface markers", "[residual][slow]") {
  // 1.5 mm deep markers: smoothing over about one marker pitch, and a 15 % weaker field.
  check_recovers("subsurface_markers", {{"depth_m", 0.0015}, {"attenuation", 0.85}});
}

TEST_CASE("residual loop attributes undeclared gravity preload", "[residual][slow]") {
  check_recovers("gravity_preload", {{"gx_px", 1.2}, {"gy_px", -0.8}, {"width_m", 0.004}});
}

TEST_CASE("residual loop attributes an undeclared edge constraint", "[residual][slow]") {
  check_recovers("edge_constraint", {{"length_m", 0.004}, {"strength", 0.6}});
}

TEST_CASE("residual loop attributes undeclared load stiffening", "[residual][slow]") {
  // beta delta = 0.4 .. 0.56 at the 1.0 .. 1.4 mm holds: the field is 29 % .. 36 % weaker than linear.
  check_recovers("load_stiffening", {{"beta_per_m", 400.0}});
}

TEST_CASE("residual loop attributes an undeclared camera misalignment", "[residual][slow]") {
  check_recovers("camera_misalignment", {{"rotation_rad", 0.06}, {"scale", 1.08}});
}

// After a pose effect is selected, later rounds hold it (every run of a fit that moves it reruns the base over
// each whole path) and the answer is refitted with everything free once the rounds are done.
TEST_CASE(
    "residual loop: a robot's tool frame and a tracker's bias, the pose effect held after its round "
    "and freed in the final refit",
    "[residual][slow]") {
  // The robot turns the sphere about a point 8 mm above its tool centre, so a press recorded tilted by t lands
  // 8 mm sin t aside (1.1 mm at 8 deg) and 8 mm (1 - cos t) deeper; its zero is 0.2 mm past the skin (the
  // 1.0-1.4 mm presses 14-20 % deeper). The tracker adds (0.3, -0.2) px to every moving marker. HydroShear, not
  // this file's fots-reimpl: FOTS's field, truncated to whole pixels, is rough in the press's depth (its RMSE
  // against these data: 0.69 / 0.15 / 0.27 / 0.10 px at a zero 0.1 / 0.2 / 0.3 / 0.4 mm deep), and a fit
  // stops in any of its valleys.
  const std::string base = "hydroshear";
  const Truths truth = {{"tool_frame", {{"pivot_depth_m", 0.008}, {"press_offset_m", 2e-4}}},
                        {"tracker_bias", {{"bias_x_px", 0.3}, {"bias_y_px", -0.2}}}};
  // Every press recorded tilted, about x or y, by 8 deg either way (a sphere turned about its centre is the same
  // sphere: only the tool frame sees the tilt).
  const auto tilted = [](std::vector<FitSample> samples) {
    const std::array<sb::Mat3, 4> tilts = {sb::Rx(0.14), sb::Ry(-0.14), sb::Rx(-0.14), sb::Ry(0.14)};
    for (std::size_t i = 0; i < samples.size(); ++i)
      for (Pose& X : samples[i].X_EI) X.linear() = tilts[i % tilts.size()] * X.linear();
    return samples;
  };
  sb::ResidualInputs in;
  in.dataset = "synthetic:tool_frame+tracker_bias";
  in.model_id = base;
  in.sensor = setup().sensor;
  in.base_params = sb::default_params(base);
  // The default gains move the pins of these presses by under 0.5 px: nothing would be scored.
  in.base_params.set("kappa_d", 20 * in.base_params.get("kappa_d"));
  in.base_params.set("kappa_s", 20 * in.base_params.get("kappa_s"));
  in.calibration = tilted(trajectories("calibration"));
  in.validation = tilted(trajectories("validation"));
  simulate(&in.calibration, truth, in.sensor, 11, base, &in.base_params);
  simulate(&in.validation, truth, in.sensor, 23, base, &in.base_params);
  sb::ResidualOptions o;
  o.max_iterations = 60;
  o.fit_base = false;
  o.candidates = {"tool_frame", "tracker_bias", "load_stiffening"};
  const auto r = sb::run_residual_loop(in, o);
  const auto j = sb::residual_to_json(r);
  INFO(j["candidates"].dump(1));
  REQUIRE(r.effects.selection.selected == std::vector<std::string>{"tool_frame", "tracker_bias"});
  REQUIRE(r.effects.final_refit.has_value());
  CHECK(j.contains("final_refit"));
  // The rounds held the zero at its round-one value while the stiffening was fitted; the final refit moves it.
  const sb::ParamSet& rounds = r.effects.fits.at("tool_frame+tracker_bias").fit.params;
  const sb::ParamSet& round_one = r.effects.fits.at("tool_frame").fit.params;
  CHECK(rounds.get("tool_frame.press_offset_m") == round_one.get("tool_frame.press_offset_m"));
  CHECK(r.after.fit.params.get("tool_frame.press_offset_m") != round_one.get("tool_frame.press_offset_m"));
  for (const auto& [effect, values] : truth)
    for (const auto& [name, value] : values) {
      const double fitted = r.after.fit.params.get(effect + "." + name);
      INFO(effect << "." << name << ": fitted " << fitted << ", injected " << value);
      CHECK(std::abs(fitted - value) <= kParamRelTol * std::abs(value));
    }
  CHECK(r.after.validation.overall.result().rmse_px < 1.3 * std::sqrt(2.0) * kNoisePx);
}

namespace {

// The four presses of each split with a tracker bias of (0.3, -0.2) px, and the loop's options that look for it alone.
sb::ResidualInputs tracker_bias_presses() {
  sb::ResidualInputs in;
  in.dataset = "synthetic:tracker_bias";
  in.model_id = kBase;
  in.sensor = setup().sensor;
  in.base_params = sb::default_params(kBase);
  in.calibration = trajectories("calibration");
  in.validation = trajectories("validation");
  const Truths truth = {{"tracker_bias", {{"bias_x_px", 0.3}, {"bias_y_px", -0.2}}}};
  simulate(&in.calibration, truth, in.sensor, 11);
  simulate(&in.validation, truth, in.sensor, 23);
  return in;
}

sb::ResidualOptions tracker_bias_options() {
  sb::ResidualOptions o;
  o.max_iterations = 15;
  o.model_forms = false;
  o.candidates = {"tracker_bias"};
  return o;
}

}  // namespace

// The search's joint refits see a subset of the calibration samples (ResidualOptions::search_samples); the answer
// is the selected set refitted on all of them, and every view says so.
TEST_CASE("residual loop: joint refits on an evenly spaced subset, the answer refitted on every calibration sample",
          "[residual]") {
  const sb::ResidualInputs in = tracker_bias_presses();
  sb::ResidualOptions o = tracker_bias_options();
  o.search_samples = 2;  // of the 4 calibration presses: the first and the third (evenly_spaced(4, 2) = 0, 2)
  const auto r = sb::run_residual_loop(in, o);
  const auto j = sb::residual_to_json(r);
  INFO(j["candidates"].dump(1));
  REQUIRE(r.effects.selection.selected == std::vector<std::string>{"tracker_bias"});
  REQUIRE(r.effects.final_refit.has_value());
  CHECK(r.effects.final_refit_why == "the search fitted it on 2 of the 4 calibration samples");
  CHECK(j["search_calibration_samples"]["fitted_on"] == 2);
  CHECK(j["search_calibration_samples"]["of"] == 4);
  CHECK(j["final_refit"]["why"] == r.effects.final_refit_why);
  // The answer is the final refit; started from the subset's optimum, its fit on all four presses can only lower
  // the calibration error over all four (Levenberg-Marquardt accepts no step that raises it).
  const sb::FitResult& rounds = r.effects.fits.at("tracker_bias").fit;
  CHECK(r.after.fit.params.get("tracker_bias.bias_x_px") ==
        r.effects.final_refit->fit.params.get("tracker_bias.bias_x_px"));
  CHECK(r.after.fit.calibration_sse_px2 <= rounds.calibration_sse_px2 * (1 + 1e-12));
  CHECK(std::abs(r.after.fit.params.get("tracker_bias.bias_x_px") - 0.3) <= kParamRelTol * 0.3);
  CHECK(sb::residual_to_markdown(r, {}).find("saw 2 of the 4 calibration samples") != std::string::npos);

  // Without a subset the joint refit already saw every sample: no final refit.
  o.search_samples = 0;
  const auto all = sb::run_residual_loop(in, o);
  CHECK_FALSE(all.effects.final_refit.has_value());
  CHECK(sb::residual_to_json(all)["search_calibration_samples"]["fitted_on"] == 4);
}

TEST_CASE("residual loop selects nothing when the data hold no effect", "[residual][slow]") {
  const auto r = run_loop("", {});
  INFO(sb::residual_to_json(r)["candidates"].dump(1));
  CHECK(r.effects.selection.selected.empty());
  // The base alone is the truth: its validation RMSE is the noise's, sqrt(2) sigma (within 15 %).
  CHECK(std::abs(r.before.validation.overall.result().rmse_px - std::sqrt(2.0) * kNoisePx) <
        0.15 * std::sqrt(2.0) * kNoisePx);

  // The report: the JSON shape the CLI promises, and one PNG per covariate plus the two quiver plots.
  const auto j = sb::residual_to_json(r);
  for (const char* key : {"dataset", "model", "before", "candidates", "selected", "after", "after_model"})
    CHECK(j.contains(key));
  CHECK(j["after_model"] == kBase);  // nothing selected: the answer is the base
  CHECK(j["before"].contains("validation_rmse_px"));
  CHECK(j["before"].contains("validation_cs"));
  CHECK(j["before"]["by_motion"].contains("shear"));
  // Every catalogued effect but the three that are the identity here: pin_lever (markers on the surface),
  // tool_frame (the poses only turn about the gel's normal) and skin_indentation (an orthographic camera).
  REQUIRE(j["candidates"].size() == sb::effect_ids().size() - 3);
  for (const auto& c : j["candidates"]) CHECK(c["effect"] != "pin_lever");
  for (const auto& c : j["candidates"]) CHECK(c["effect"] != "tool_frame");
  for (const auto& c : j["candidates"]) CHECK(c["effect"] != "skin_indentation");
  for (const auto& c : j["candidates"]) CHECK(c["ci95_pct"].size() == 2);
  const auto dir = sbtest::temp_path("sb_test_residual_plots");
  std::filesystem::create_directories(dir);
  const auto plots = sb::write_residual_plots(r, dir.string(), "r");
  // One per covariate table, the mean residual and PC1, and one panel row per binned covariate (depth, travel and
  // tilt direction); nothing was selected, so no "after" plots.
  REQUIRE(r.structure_before.binned_fields.size() == 3);
  CHECK(plots.size() == r.structure_before.covariates.size() + 2 + 3);
  for (const auto& name : plots) CHECK(std::filesystem::file_size(dir / name) > 0);
  CHECK(sb::residual_to_markdown(r, plots).find("Selected: nothing") != std::string::npos);
  std::filesystem::remove_all(dir);
}

TEST_CASE("residual structure: a rank-one residual is one principal component, binned counts add up", "[residual]") {
  // meas = base prediction + a_k u_j with u_j = (1, 0) on even markers and (0, 1) on odd ones and
  // a_k = 0.1 (1 + k mod 3) px. Centred over frames the residual is (a_k - mean a) u_j: rank one, so PC1
  // explains all of its variance and points along u; the mean field is (mean a) u_j.
  constexpr double kTol = 1e-9;
  auto s = press("one", "shear", "calibration", Vec2(1e-3, 0), 1.2e-3, Vec2(0.6e-3, 0), 0);
  auto model = sb::make_model(kBase, setup().sensor, s.indenter);
  s.meas_px = sb::simulate_sample(*model, s);
  const auto u = [](std::size_t j) { return j % 2 == 0 ? Vec2(1, 0) : Vec2(0, 1); };
  const auto a = [](std::size_t k) { return 0.1 * (1 + k % 3); };
  for (std::size_t k = 0; k < s.meas_px.size(); ++k)
    for (std::size_t j = 0; j < s.meas_px[k].size(); ++j) s.meas_px[k][j] += a(k) * u(j);
  double biggest = 0;
  for (auto& f : s.meas_px)
    for (auto& d : f) biggest = std::max(biggest, d.norm());
  INFO("largest measured displacement " << biggest << " px");
  const auto st = sb::analyse_residual(kBase, sb::default_params(kBase), setup().sensor, {s}, 5);
  REQUIRE(st.frames > 2);
  REQUIRE(st.explained_variance.size() == 3);
  CHECK(st.explained_variance[0] == Approx(1.0).margin(kTol));
  CHECK(st.explained_variance[1] == Approx(0.0).margin(kTol));
  // The mean of a over the scored frames, read back from marker 0 (u = (1, 0)) and marker 1 (u = (0, 1)).
  const double mean_a = st.mean_field_px[0].x();
  CHECK(mean_a > 0.1 - kTol);
  CHECK(mean_a < 0.3 + kTol);
  CHECK(st.mean_field_px[1].y() == Approx(mean_a).margin(kTol));
  CHECK(std::abs(st.mean_field_px[0].y()) < kTol);
  for (std::size_t j = 0; j < st.pc1_px.size(); ++j) {
    const Vec2 v = st.pc1_px[j];
    CHECK(std::abs(v.x() * u(j).y() - v.y() * u(j).x()) < kTol);  // parallel to u_j
  }
  long in_contact = -1;
  for (const auto& t : st.covariates) {
    long n = 0;
    for (long c : t.count) n += c;
    INFO(t.name);
    if (!t.contact_frame) CHECK(n == st.marker_frames);
    if (t.name == "contact frame: phase") in_contact = n;
  }
  // The contact-frame tables hold the marker-frames in contact: the three sides of the edge table together,
  // and the load table, hold as many as the phase table.
  long sides = 0, load = 0;
  for (const auto& t : st.covariates)
    for (long c : t.count) {
      if (t.name.rfind("contact frame: distance", 0) == 0) sides += c;
      if (t.name.rfind("contact frame: normal load", 0) == 0) load += c;
    }
  CHECK(in_contact > 0);
  CHECK(in_contact <= st.marker_frames);
  CHECK(sides == in_contact);
  CHECK(load == in_contact);

  // The binned mean fields: depth, travel and tilt bins each partition the frames in contact, so their
  // frame-weighted means agree (the mean of a_k over those frames, along u_j); the slide goes +x only, and
  // the sphere never tilts.
  REQUIRE(st.binned_fields.size() == 3);
  std::vector<double> weighted_mean;
  std::vector<long> total_frames;
  for (const auto& b : st.binned_fields) {
    INFO(b.name);
    REQUIRE(b.mean_px.size() == b.labels.size());
    long n = 0;
    double sum = 0;
    for (std::size_t k = 0; k < b.labels.size(); ++k) {
      n += b.frames[k];
      sum += b.frames[k] * b.mean_px[k][0].x();
      if (b.frames[k] > 0) CHECK(b.mean_px[k][1].y() == Approx(b.mean_px[k][0].x()).margin(kTol));
      if (b.frames[k] > 0) CHECK(std::abs(b.mean_px[k][0].y()) < kTol);
    }
    total_frames.push_back(n);
    weighted_mean.push_back(n > 0 ? sum / n : -1);
  }
  CHECK(total_frames[0] > 0);
  CHECK(total_frames[1] == total_frames[0]);
  CHECK(total_frames[2] == total_frames[0]);
  CHECK(weighted_mean[0] > 0.1 - kTol);
  CHECK(weighted_mean[0] < 0.3 + kTol);
  CHECK(weighted_mean[1] == Approx(weighted_mean[0]).margin(kTol));
  CHECK(weighted_mean[2] == Approx(weighted_mean[0]).margin(kTol));
  const auto& travel = st.binned_fields[1];
  CHECK(travel.frames[1] > 0);                              // +x
  CHECK(travel.frames[3] == 0);                             // -x
  CHECK(st.binned_fields[2].frames[0] == total_frames[0]);  // all untilted
}

// The contact-frame tables read a residual in the contact's own frame. Two residuals are added to the
// base prediction of a press that slides 0.8 mm along +x:
//  - a radial field 0.2 px r_hat (r_hat from the contact centre, as indenter_penetration places it, to
//    the marker): its radial component is 0.2 px in every bin of every contact-frame table;
//  - a uniform field (0.3, 0) px: its component along the travel (+x once the sphere has moved) is 0.3 px
//    on the leading and trailing sides and 0 where it has not travelled yet; its radial component
//    0.3 (r_hat . x) is >= 0 ahead of the centre (leading) and <= 0 behind it (trailing).
TEST_CASE("residual structure: the contact frame's radial and along-travel components", "[residual]") {
  constexpr double kTol = 1e-9;
  const auto& sensor = *setup().sensor;
  auto s = press("cf", "shear", "calibration", Vec2(0.5e-3, 0.3e-3), 1.2e-3, Vec2(0.8e-3, 0), 0);
  auto model = sb::make_model(kBase, setup().sensor, s.indenter);
  const auto base = sb::simulate_sample(*model, s);
  const auto table = [](const sb::ResidualStructure& st, const std::string& name) -> const sb::CovariateTable& {
    for (const auto& t : st.covariates)
      if (t.name == name) return t;
    FAIL("no covariate table " << name);
    return st.covariates.front();
  };
  const std::string leading = "contact frame: distance outside the contact edge, leading side";
  const std::string trailing = "contact frame: distance outside the contact edge, trailing side";
  const std::string no_travel = "contact frame: distance outside the contact edge, no travel side";

  s.meas_px = base;
  for (std::size_t k = 0; k < s.X_EI.size(); ++k) {
    const sb::Penetration pen = sb::indenter_penetration(*sensor.gel_sdf, *s.indenter, s.X_EI[k]);
    for (std::size_t j = 0; j < sensor.p_EM.size(); ++j)
      s.meas_px[k][j] += 0.2 * (sensor.p_EM[j].head<2>() - pen.centre_E).normalized();
  }
  const auto radial = sb::analyse_residual(kBase, sb::default_params(kBase), setup().sensor, {s}, 5);
  for (const auto& t : radial.covariates) {
    if (!t.contact_frame) continue;
    for (std::size_t b = 0; b < t.labels.size(); ++b) {
      if (t.count[b] == 0) continue;
      INFO(t.name << " bin " << t.labels[b]);
      CHECK(t.mean_radial_px[b] == Approx(0.2).margin(kTol));
    }
  }

  s.meas_px = base;
  for (auto& frame : s.meas_px)
    for (auto& d : frame) d += Vec2(0.3, 0.0);
  const auto uniform = sb::analyse_residual(kBase, sb::default_params(kBase), setup().sensor, {s}, 5);
  long n_lead = 0, n_trail = 0;
  for (const auto& [name, along, sign] :
       {std::tuple{leading, 0.3, 1}, std::tuple{trailing, 0.3, -1}, std::tuple{no_travel, 0.0, 0}}) {
    const auto& t = table(uniform, name);
    for (std::size_t b = 0; b < t.labels.size(); ++b) {
      if (t.count[b] == 0) continue;
      INFO(name << " bin " << t.labels[b]);
      CHECK(t.mean_along_px[b] == Approx(along).margin(kTol));
      if (sign > 0) CHECK(t.mean_radial_px[b] >= -kTol);
      if (sign < 0) CHECK(t.mean_radial_px[b] <= kTol);
      (sign > 0 ? n_lead : n_trail) += sign != 0 ? t.count[b] : 0;
    }
  }
  CHECK(n_lead > 0);
  CHECK(n_trail > 0);
}

// The search sees a search set of both splits (ResidualOptions::search_set); what is reported of the base and the
// answer is refitted and scored on every sample.
TEST_CASE("residual loop: the search on a search set, the base and the answer refitted and scored on all samples",
          "[residual]") {
  const sb::ResidualInputs in = tracker_bias_presses();
  sb::ResidualOptions o = tracker_bias_options();
  // 6 of the 8 samples: each split's share 6 * 4 / 8 = 3, evenly spaced (evenly_spaced(4, 3) = 0, 1, 2).
  o.search_set = 6;
  constexpr std::size_t kSearchedPerSplit = 3;
  const auto r = sb::run_residual_loop(in, o);
  const auto j = sb::residual_to_json(r);
  INFO(j["candidates"].dump(1));
  CHECK(r.search_set_samples == 2 * kSearchedPerSplit);
  CHECK(j["search_set_samples"]["searched"] == 2 * kSearchedPerSplit);
  CHECK(j["search_set_samples"]["of"] == 8);
  REQUIRE(r.effects.selection.selected == std::vector<std::string>{"tracker_bias"});
  // The search's scores are the search set's: one validation error per searched validation sample.
  CHECK(r.effects.fits.at("tracker_bias").fit.validation.sq_err_px2.size() == kSearchedPerSplit);
  CHECK(r.effects.fits.at("").fit.validation.sq_err_px2.size() == kSearchedPerSplit);
  // The base and the answer are every sample's: refitted on all 4 calibration presses, scored on all 4 held out.
  CHECK(r.before.fit.validation.sq_err_px2.size() == in.validation.size());
  CHECK(r.after.fit.validation.sq_err_px2.size() == in.validation.size());
  REQUIRE(r.effects.final_refit.has_value());
  CHECK(r.effects.final_refit_why == "the search fitted it on 3 of the 4 calibration samples");
  CHECK(std::abs(r.after.fit.params.get("tracker_bias.bias_x_px") - 0.3) <= kParamRelTol * 0.3);
  CHECK(sb::residual_to_markdown(r, {}).find("saw 6 of the 8 samples") != std::string::npos);

  // A search set as large as the set is the set: nothing refitted for it.
  o.search_set = 8;
  const auto whole = sb::run_residual_loop(in, o);
  CHECK(whole.search_set_samples == 8);
  CHECK_FALSE(whole.effects.final_refit.has_value());
}

}  // namespace test_residual
