// core/workbench/report_dataset: a residual analysis is shown only over the dataset it was computed on.
#include <catch2/catch.hpp>

#include "temp_path.hpp"

#include <filesystem>
#include <fstream>

#include "core/workbench/report_dataset.hpp"

// This file's names in a namespace of its own: the unity build compiles several test files as one unit.
namespace test_report_dataset {

namespace fs = std::filesystem;

TEST_CASE("A dataset's name is its folder's last component, however it is written", "[report_dataset]") {
  CHECK(sb::dataset_name("data:twin/twin_sphere35") == "twin_sphere35");
  CHECK(sb::dataset_name("/data/twin/twin_frames/") == "twin_frames");
  CHECK(sb::dataset_name("twin_torus") == "twin_torus");
  CHECK(sb::dataset_name("").empty());
}

TEST_CASE("A report over another dataset or a scene is refused, naming both", "[report_dataset]") {
  // twin_sphere35's report over twin_frames replaced HydroShear's panel with its answer on the wrong data.
  const auto wrong = sb::check_report_dataset("residual.json", "twin_sphere35", "data:twin/twin_frames");
  CHECK_FALSE(wrong.load);
  CHECK_THAT(wrong.message,
             Catch::Contains("twin_sphere35") && Catch::Contains("twin_frames") && Catch::Contains("not loaded"));
  const auto scene = sb::check_report_dataset("residual.json", "twin_sphere35", "");
  CHECK_FALSE(scene.load);
  CHECK_THAT(scene.message, Catch::Contains("scene"));
  // Its own dataset, however the folder is written.
  CHECK(sb::check_report_dataset("r.json", "twin_sphere35", "/x/twin/twin_sphere35/").load);
  // A report naming no dataset loads, with a note.
  const auto old = sb::check_report_dataset("r.json", "", "data:twin/twin_frames");
  CHECK(old.load);
  CHECK_THAT(old.message, Catch::Contains("names no dataset"));
}

TEST_CASE("A report opens its own dataset when the data root has it", "[report_dataset]") {
  const fs::path root = sbtest::temp_path("sb_test_report_dataset_root");
  fs::create_directories(root / "twin" / "twin_a");
  std::ofstream(root / "twin" / "twin_a" / "dataset.json") << "{}";
  fs::create_directories(root / "raw" / "real_b");
  std::ofstream(root / "raw" / "real_b" / "dataset.json") << "{}";
  fs::create_directories(root / "twin" / "no_json");
  const std::string r = root.string();
  CHECK(sb::report_dataset_path("twin_a", r) == "data:twin/twin_a");
  CHECK(sb::report_dataset_path("real_b", r) == "data:raw/real_b");
  CHECK(sb::report_dataset_path("no_json", r).empty());
  CHECK(sb::report_dataset_path("twin_a+lens_distortion", r).empty());  // an injected set is not on disk
  CHECK(sb::report_dataset_path("../twin/twin_a", r).empty());
  CHECK(sb::report_dataset_path("twin_a", "").empty());
  fs::remove_all(root);
}

}  // namespace test_report_dataset
