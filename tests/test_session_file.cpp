// core/session_file: the workbench session document.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>

#include <unistd.h>

#include "core/base/error.hpp"
#include "core/workbench/session_file.hpp"

// This file's names in a namespace of its own: the unity build (CMAKE_UNITY_BUILD) compiles several
// test files as one translation unit.
namespace test_session_file {

namespace {

namespace fs = std::filesystem;
constexpr double kPoseTol = 1e-12;  // poses go through JSON doubles (17 significant digits): exact to rounding

std::string temp_file(const std::string& name, const std::string& text) {
  const fs::path p = fs::temp_directory_path() / ("sb_session_" + std::to_string(::getpid()) + "_" + name);
  std::ofstream(p) << text;
  return p.string();
}

std::string message_of(const std::string& text) {
  try {
    sb::session_from_json(nlohmann::json::parse(text), "s.json");
  } catch (const sb::InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("a session survives a save and a load unchanged", "[session]") {
  sb::SessionFile s;
  s.open.dataset_dir = "data:twin/twin_sphere8";
  s.open.sample_id = "shr_01";
  s.open.tacsl_id = "tacsl-normalized";
  s.open.beside_hydroshear = "hydroshear-layer-stick";
  s.params["hydroshear"] = {{"mu", 0.4}};
  s.path = {sb::Pose::Identity(),
            sb::make_pose(sb::Vec3(1e-3, -2e-3, 0.5e-3), sb::Quat(Eigen::AngleAxisd(0.3, sb::Vec3::UnitZ())))};
  s.step = 1;
  s.auto_scale = false;
  s.arrow_gain = 150;
  s.residual_file = "/analyses/twin_sphere8_tacsl.json";
  s.residual_fields = true;
  s.residual_corrected = false;
  s.camera = sb::CameraView{sb::Vec3(10, -20, 30), sb::Vec3(1, 2, 0), sb::Vec3(0, 0, 1)};
  const std::string path = temp_file("rt.json", "");
  sb::save_session_file(path, s);
  const sb::SessionFile r = sb::load_session_file(path);
  CHECK(r.open.dataset_dir == s.open.dataset_dir);
  CHECK(r.open.sample_id == "shr_01");
  CHECK(r.open.tacsl_id == "tacsl-normalized");
  CHECK(r.open.beside_hydroshear == "hydroshear-layer-stick");
  CHECK(r.params == s.params);
  REQUIRE(r.path.size() == 2);
  CHECK((r.path[1].matrix() - s.path[1].matrix()).cwiseAbs().maxCoeff() < kPoseTol);
  CHECK(r.step == 1);
  CHECK_FALSE(r.auto_scale);
  CHECK(r.arrow_gain == 150);
  CHECK(r.residual_file == s.residual_file);
  CHECK(r.residual_fields);
  CHECK_FALSE(r.residual_corrected);
  // The 3D view's orbit comes back too (the README says the view is saved).
  REQUIRE(r.camera);
  CHECK(r.camera->position == s.camera->position);
  CHECK(r.camera->focal_point == s.camera->focal_point);
  // What the display was set to: the 3D markers' model, the colour map, each panel's frame backdrop.
  s.marker_model = "fots-reimpl";
  s.colour_map = sb::ColourMap::kHighContrast;
  s.frame_backdrops = {{"FOTS", sb::FrameBackdrop::kRaw}, {"Measured", sb::FrameBackdrop::kOutlined}};
  sb::save_session_file(path, s);
  const sb::SessionFile shown = sb::load_session_file(path);
  CHECK(shown.marker_model == "fots-reimpl");
  CHECK(shown.colour_map == sb::ColourMap::kHighContrast);
  CHECK(shown.frame_backdrops == s.frame_backdrops);
  // Without an analysis the section is left out, and reads back as none; so is an empty beside panel (the
  // key is absent, and files without the feature stay readable by older builds).
  s.residual_file.clear();
  s.open.beside_hydroshear.clear();
  sb::save_session_file(path, s);
  CHECK(sb::load_session_file(path).residual_file.empty());
  CHECK_FALSE(sb::session_to_json(s)["open"].contains("beside_hydroshear"));
  // The display's choices at their defaults are left out too.
  s.marker_model.clear();
  s.colour_map = sb::ColourMap::kViridis;
  s.frame_backdrops.clear();
  for (const char* key : {"marker_model", "colour_map", "frame_backdrops"})
    CHECK_FALSE(sb::session_to_json(s)["display"].contains(key));
  fs::remove(path);
}

TEST_CASE("bad session files name the file and the JSON pointer", "[session]") {
  const std::string head = R"({"format": "shearbench-session", "version": 1, "open": {})";
  CHECK_THAT(message_of(R"({"format": "other", "version": 1, "open": {}})"), Catch::Contains("s.json: /format"));
  CHECK_THAT(message_of(R"({"format": "shearbench-session", "version": 7, "open": {}})"),
             Catch::Contains("/version") && Catch::Contains("unsupported session version 7"));
  CHECK_THAT(message_of(head + R"(, "path_X_EI": [[0, 0, 0, 1, 0, 0]]})"), Catch::Contains("/path_X_EI/0"));
  CHECK_THAT(message_of(head + R"(, "path_X_EI": [[0, 0, 0, 0, 0, 0, 0]]})"), Catch::Contains("/path_X_EI/0"));
  CHECK_THAT(message_of(head + R"(, "path_X_EI": [[0, 0, 0, 1, 0, 0, 0]], "step": 3})"), Catch::Contains("/step"));
  CHECK_THAT(message_of(head + R"(, "params": {"tacsl": 3}})"), Catch::Contains("/params/tacsl"));
  CHECK_THAT(message_of(head + R"(, "display": {"arrow_gain": -1}})"), Catch::Contains("/display/arrow_gain"));
  CHECK_THAT(message_of(head + R"(, "colour": 1})"), Catch::Contains("colour"));  // a typo is not ignored
  CHECK_THAT(message_of(head + R"(, "display": {"colour_map": "jet"}})"),
             Catch::Contains("/display/colour_map") && Catch::Contains("'viridis'") && Catch::Contains("'jet'"));
  CHECK_THAT(message_of(head + R"(, "display": {"frame_backdrops": {"FOTS": "dark"}}})"),
             Catch::Contains("/display/frame_backdrops/FOTS"));
  CHECK_THAT(message_of(R"([1, 2])"), Catch::Contains("s.json"));
  // Version 1 had no residual section: a reader of version 1 rejected it as an unknown key, so a file
  // that has one is version 2, and a version 1 file claiming one is refused.
  CHECK_THAT(message_of(head + R"(, "residual": {"file": "r.json"}})"),
             Catch::Contains("/residual") && Catch::Contains("version 1"));
  CHECK_THAT(message_of(R"({"format": "shearbench-session", "version": 0, "open": {}})"),
             Catch::Contains("reads 1 to 4"));
}

TEST_CASE("a session file that is not JSON is reported with its line", "[session]") {
  const std::string path = temp_file("broken.json", "{\n  \"format\": \"shearbench-session\",\n  oops\n}\n");
  try {
    sb::load_session_file(path);
    FAIL("expected an InputError");
  } catch (const sb::InputError& e) {
    CHECK(e.file() == path);
    CHECK(e.line() == 3);
  }
  fs::remove(path);
}

TEST_CASE("a save never overwrites a file that is not a session file", "[session]") {
  // A scene file the user pointed the Session field at (the quit dialog then offered to save over it).
  const std::string scene_text =
      "{\n  \"description\": \"press the cow\",\n  \"indenter\": {\"shape\": \"sphere\"}\n}\n";
  const std::string scene = temp_file("scene.json", scene_text);
  sb::SessionFile s;
  s.step = 0;
  s.path = {sb::Pose::Identity()};
  CHECK_FALSE(sb::is_session_file(scene));
  try {
    sb::save_session_file(scene, s);
    FAIL("expected an InputError");
  } catch (const sb::InputError& e) {
    CHECK(e.file() == scene);
    CHECK_THAT(e.what(), Catch::Contains("not a shearbench session file") && Catch::Contains("not overwritten"));
  }
  std::ifstream in(scene);
  const std::string after((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  CHECK(after == scene_text);  // byte for byte
  // Not JSON at all, and a folder: refused too.
  const std::string text = temp_file("notes.txt", "my notes\n");
  CHECK_THROWS_AS(sb::save_session_file(text, s), sb::InputError);
  CHECK_THROWS_AS(sb::save_session_file(fs::temp_directory_path().string(), s), sb::InputError);
  // A session file (even one this build cannot read) and a new file: written.
  const std::string old_session = temp_file("old.json", R"({"format": "shearbench-session", "version": 99})");
  CHECK(sb::is_session_file(old_session));
  CHECK_NOTHROW(sb::save_session_file(old_session, s));
  CHECK(sb::load_session_file(old_session).step == 0);
  const std::string fresh =
      (fs::temp_directory_path() / ("sb_session_fresh_" + std::to_string(::getpid()) + ".json")).string();
  fs::remove(fresh);
  CHECK_NOTHROW(sb::save_session_file(fresh, s));
  for (const auto& p : {scene, text, old_session, fresh}) fs::remove(p);
}

}  // namespace test_session_file
