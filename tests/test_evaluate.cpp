#include <unistd.h>
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>

#include "core/calibration/evaluate.hpp"

// This file's names in a namespace of its own: the unity build (CMAKE_UNITY_BUILD) compiles several
// test files as one translation unit.
namespace test_evaluate {

using namespace sb;
namespace fs = std::filesystem;

namespace {

constexpr double kTol = 1e-12;  // sums of a few exact small numbers

// A model whose field is known: every marker moves by (x_I / 1 mm) px along u, i.e. the indenter's x
// position in millimetres. It also records the dt it was stepped with.
class XInMillimetresModel : public ShearModel {
 public:
  explicit XInMillimetresModel(std::size_t markers) : markers_(markers) {}
  std::string id() const override { return "x-mm"; }
  const ParamSet& params() const override { return params_; }
  void set_params(const ParamSet& p) override { params_ = p; }
  void reset() override { ++resets; }
  void step(const Pose& X_EI, double dt, FieldOutput* out) override {
    last_dt = dt;
    out->disp_px.assign(markers_, Vec2(X_EI.translation().x() * 1e3, 0));
  }
  std::unique_ptr<ShearModel> clone() const override { return std::make_unique<XInMillimetresModel>(*this); }
  int resets = 0;
  double last_dt = 0;

 private:
  std::size_t markers_;
  ParamSet params_;
};

struct TempDir {
  fs::path path = fs::temp_directory_path() / ("sb_eval_" + std::to_string(::getpid()));
  TempDir() { fs::create_directories(path / "meshes"); }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
};

// Two one-marker samples, shear (calibration) and twist (validation), two frames each.
// shr: x = 0, 2 mm; measured 0, 1 px. Frame 0 does not move (|meas| < 0.5): skipped. Frame 1: pred 2,
//      meas 1: |e|^2 = 1, cos 1.
// twi: x = 0, 1 mm; measured (0, 0) and (0, 3) px. Frame 1: pred (1, 0), meas (0, 3): |e|^2 = 1 + 9 = 10,
//      cos 0.
Dataset make_dataset(const fs::path& dir) {
  std::ofstream(dir / "meshes" / "m.obj") << "v 0 0 0\n";
  Dataset ds;
  ds.dir = dir.string();
  ds.name = "eval";
  ds.markers_rest_px = {Vec2(10, 10)};
  ds.indenters["m"] = TsdIndenter{"meshes/m.obj", nlohmann::json::object()};
  std::vector<SampleData> data;
  auto add = [&](const char* id, const char* motion, const char* split, double x1_m, Vec2 meas1) {
    TsdSampleInfo info;
    info.id = id;
    info.motion = motion;
    info.split = split;
    info.indenter = "m";
    info.dt_s = 0.05;
    ds.samples.push_back(info);
    SampleData d;
    d.push_pose(0, Pose::Identity());
    Pose X = Pose::Identity();
    X.translation().x() = x1_m;
    d.push_pose(0.05, X);
    d.markers_px = {{Vec2(0, 0)}, {meas1}};
    data.push_back(d);
  };
  add("shr", "shear", "calibration", 0.002, Vec2(1, 0));
  add("twi", "twist", "validation", 0.001, Vec2(0, 3));
  write_dataset(dir.string(), ds, data);
  return read_dataset(dir.string());
}

}  // namespace

TEST_CASE("evaluate: per-motion and overall bookkeeping with a known model", "[metrics]") {
  TempDir t;
  const Dataset ds = make_dataset(t.path);
  int made = 0;
  const ModelFactory factory = [&](const TsdSampleInfo&) {
    ++made;
    return std::make_unique<XInMillimetresModel>(1);
  };
  const EvaluationResult all = evaluate_dataset(ds, factory, "all", "x-mm");
  CHECK(made == 2);
  const MetricsResult shear = all.metrics.per_motion.at("shear").result();
  const MetricsResult twist = all.metrics.per_motion.at("twist").result();
  CHECK(shear.n == 1);
  CHECK(std::abs(shear.rmse_px - 1.0) < kTol);
  CHECK(std::abs(shear.cs - 1.0) < kTol);
  CHECK(std::abs(twist.rmse_px - std::sqrt(10.0)) < kTol);
  CHECK(std::abs(twist.cs - 0.0) < kTol);
  // Overall: (1 + 10) / 2 -> RMSE sqrt(5.5); CS (1 + 0) / 2.
  const MetricsResult o = all.metrics.overall.result();
  CHECK(o.n == 2);
  CHECK(std::abs(o.rmse_px - std::sqrt(5.5)) < kTol);
  CHECK(std::abs(o.cs - 0.5) < kTol);
  REQUIRE(all.samples.size() == 2);
  CHECK(all.samples[0].sample_id == "shr");

  const EvaluationResult cal = evaluate_dataset(ds, factory, "calibration", "x-mm");
  CHECK(cal.metrics.per_motion.count("twist") == 0);
  CHECK(cal.metrics.overall.result().n == 1);
  CHECK_THROWS_AS(evaluate_dataset(ds, factory, "test", "x-mm"), InputError);

  const std::string md = evaluation_to_markdown({all}, "eval");
  CHECK_THAT(md, Catch::Matchers::Contains("Shear RMSE (px) | Shear CS"));
  CHECK_THAT(md, Catch::Matchers::Contains("| 1.000 | 1.000 |"));  // shear pair
  const auto j = evaluation_to_json({all}, ds, "all");
  CHECK(j["models"]["x-mm"]["overall"]["n"] == 2);
}

TEST_CASE("evaluate: run_sample resets the model and steps with the sample's dt", "[metrics]") {
  XInMillimetresModel model(1);
  SampleData d;
  d.push_pose(0, Pose::Identity());
  d.markers_px = {{Vec2(0, 0)}};
  MetricsAccumulator acc;
  run_sample(model, d, 0.125, &acc);
  CHECK(model.resets == 1);
  CHECK(model.last_dt == 0.125);
}

TEST_CASE("evaluate: params files keyed by model id or flat", "[metrics]") {
  const auto keyed = nlohmann::json::parse(R"({"hydroshear": {"mu": 0.4}, "fots": {"lambda": 3}})");
  CHECK(params_for_model(keyed, "fots", false, "p.json") == nlohmann::json::parse(R"({"lambda": 3})"));
  CHECK(params_for_model(keyed, "tacsl", false, "p.json").empty());
  const auto flat = nlohmann::json::parse(R"({"mu": 0.4})");
  CHECK(params_for_model(flat, "hydroshear", true, "p.json") == flat);
  CHECK_THROWS_WITH(params_for_model(flat, "hydroshear", false, "p.json"), Catch::Matchers::Contains("p.json"));
  CHECK_THROWS_AS(params_for_model(nlohmann::json::parse(R"({"mu": "x"})"), "hydroshear", true, "p.json"), InputError);
}

TEST_CASE("scored_fields_csv: one row per scored marker, NaN where the tracker lost it", "[evaluate]") {
  sb::EvaluationResult r;
  r.model_id = "hydroshear";
  sb::SampleEvaluation s;
  s.sample_id = "val_0001";
  s.motion = "shear";
  const double nan = std::numeric_limits<double>::quiet_NaN();
  s.fields.push_back({11, {sb::Vec2(1.25, -2), sb::Vec2(0.5, 0.5)}, {sb::Vec2(1, -2.5), sb::Vec2(nan, nan)}});
  r.samples.push_back(s);
  CHECK(sb::scored_fields_csv(r) ==
        "sample,motion,frame,marker,meas_du_px,meas_dv_px,pred_du_px,pred_dv_px\n"
        "val_0001,shear,11,0,1.0000,-2.5000,1.2500,-2.0000\n"
        "val_0001,shear,11,1,nan,nan,0.5000,0.5000\n");
}

}  // namespace test_evaluate
