// core/field_export: the workbench's field export, on its own and on the worker thread.
#include <catch2/catch.hpp>

#include <unistd.h>
#include <filesystem>
#include <fstream>

#include "core/base/error.hpp"
#include "core/calibration/prediction_export.hpp"
#include "core/data/tsd.hpp"
#include "core/workbench/field_export.hpp"
#include "model_fixtures.hpp"

// This file's names in a namespace of its own: the unity build (CMAKE_UNITY_BUILD) compiles several
// test files as one translation unit.
namespace test_field_export {

namespace fs = std::filesystem;
using namespace sbtest;

namespace {

constexpr double kRadiusM = 0.004;

struct TempDir {
  fs::path path = fs::temp_directory_path() / ("sb_field_export_" + std::to_string(::getpid()));
  TempDir() { fs::remove_all(path); }
  ~TempDir() { fs::remove_all(path); }
};

// Press the sphere 1 mm into the pad over the first half of the steps, then slide it 2 mm along +x.
std::vector<Pose> press_then_slide(int steps) {
  std::vector<Pose> path;
  const int half = steps / 2;
  for (int k = 0; k < steps; ++k) {
    const double depth = 1e-3 * std::min(1.0, double(k + 1) / half);
    const double x = k < half ? 0.0 : 2e-3 * double(k - half + 1) / (steps - half);
    path.push_back(sphere_pose(kRadiusM, x, 0, depth));
  }
  return path;
}

FieldExportRequest request(const fs::path& dir, int steps) {
  IndenterSpec spec;
  spec.shape = "sphere";
  spec.radius_m = kRadiusM;
  FieldExportRequest r;
  r.dir = dir.string();
  r.title = "test";
  r.sensor = test_sensor();
  r.indenter = std::make_shared<const Indenter>(build_indenter(spec, "", ""));
  r.models = {{"hydroshear", default_params("hydroshear")}, {"tacsl", default_params("tacsl")}};
  r.path = press_then_slide(steps);
  r.dt_s = 0.01;
  return r;
}

}  // namespace

TEST_CASE("an exported field reads back as the model's field along the path", "[field_export]") {
  // The markers are written as the shortest text that reads back to the same double, so the read-back
  // equals a fresh run of the same model exactly.
  constexpr double kMinFieldPx = 0.1;  // the press and slide must give a field worth comparing
  TempDir tmp;
  const FieldExportRequest req = request(tmp.path, 40);
  REQUIRE(export_fields(req) == 2);
  for (const auto& m : req.models) {
    const Dataset ds = read_dataset((tmp.path / m.id).string());
    REQUIRE(ds.extra.at("shearbench").at("export") == true);
    REQUIRE(ds.extra.at("shearbench").at("model") == m.id);
    const SampleData back = read_sample(ds, "path");
    auto model = make_model(m.id, req.sensor, req.indenter);
    model->set_params(m.params);
    const auto expected = predict_along(*model, req.path, req.dt_s);
    REQUIRE(back.markers_px.size() == expected.size());
    double largest = 0;
    for (std::size_t k = 0; k < expected.size(); ++k)
      for (std::size_t j = 0; j < expected[k].size(); ++j) {
        REQUIRE(back.markers_px[k][j] == expected[k][j]);
        largest = std::max(largest, expected[k][j].norm());
      }
    CHECK(largest > kMinFieldPx);
  }
  // An earlier export may be replaced.
  CHECK(export_fields(req) == 2);
}

TEST_CASE("a field export never writes into a folder that is not an earlier export", "[field_export]") {
  TempDir tmp;
  const FieldExportRequest req = request(tmp.path, 10);
  fs::create_directories(tmp.path / "tacsl");
  { std::ofstream(tmp.path / "tacsl" / "notes.txt") << "mine"; }
  SECTION("a folder without dataset.json") {}
  SECTION("a tsd/1 folder that is not an export") {
    std::ofstream(tmp.path / "tacsl" / "dataset.json") << R"({"format": "tsd/1"})";
  }
  REQUIRE_THROWS_AS(export_fields(req), InputError);
  CHECK_THROWS_WITH(check_export_target(req), Catch::Contains("not a shearbench field export"));
  // Refused before anything is computed: the other model's folder was not written either.
  CHECK_FALSE(fs::exists(tmp.path / "hydroshear"));
  std::ifstream notes(tmp.path / "tacsl" / "notes.txt");
  std::string text;
  notes >> text;
  CHECK(text == "mine");
}

TEST_CASE("a field export cancelled while computing writes nothing", "[field_export]") {
  // Two models x 200 steps: the first report comes after kPredictReportEvery = 64 steps of the first
  // model, at 64 / 400 of the whole; cancelling there stops the export before any write.
  TempDir tmp;
  const FieldExportRequest req = request(tmp.path, 200);
  std::atomic<bool> cancel{false};
  std::vector<double> fractions;
  Progress p;
  p.cancel = &cancel;
  p.report = [&](const std::string& stage, double fraction) {
    CHECK(stage == "hydroshear");
    fractions.push_back(fraction);
    cancel = true;
  };
  REQUIRE_THROWS_AS(export_fields(req, p), Cancelled);
  REQUIRE(fractions.size() == 1);
  CHECK(fractions[0] == Approx(64.0 / 400.0));
  CHECK_FALSE(fs::exists(tmp.path));
}

TEST_CASE("the export job ends Done, Failed or Cancelled and says so", "[field_export]") {
  TempDir tmp;
  FieldExportJob job;
  SECTION("done") {
    job.start(request(tmp.path, 20));
    job.wait();
    const FieldExportStatus s = job.status();
    REQUIRE(s.phase == FieldExportStatus::Phase::kDone);
    CHECK(s.written == 2);
    CHECK(s.fraction == 1.0);
    CHECK(fs::exists(tmp.path / "hydroshear" / "dataset.json"));
  }
  SECTION("failed: an empty path") {
    FieldExportRequest r = request(tmp.path, 20);
    r.path.clear();
    job.start(r);
    job.wait();
    const FieldExportStatus s = job.status();
    REQUIRE(s.phase == FieldExportStatus::Phase::kFailed);
    CHECK_THAT(s.error, Catch::Contains("path is empty"));
  }
  SECTION("cancelled") {
    // 2 x 20000 HydroShear and TacSL steps take well over a second; the cancel comes microseconds
    // after the start.
    job.start(request(tmp.path, 20000));
    job.cancel();
    job.wait();
    REQUIRE(job.status().phase == FieldExportStatus::Phase::kCancelled);
    CHECK_FALSE(fs::exists(tmp.path));
  }
}

}  // namespace test_field_export
