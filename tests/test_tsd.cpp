#include <catch2/catch.hpp>

#include <unistd.h>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include "mini_grid.hpp"

#include "core/base/data_root.hpp"
#include "core/base/error.hpp"
#include "core/data/tsd.hpp"

// This file's names in a namespace of its own: the unity build (CMAKE_UNITY_BUILD) compiles several
// test files as one translation unit.
namespace test_tsd {

using sbtest::kMiniMarkers;

using namespace sb;
namespace fs = std::filesystem;

namespace {

// A fresh, empty folder under the system temp dir, removed when the test ends.
struct TempDir {
  fs::path path;
  TempDir() {
    static int counter = 0;
    path = fs::temp_directory_path() / ("sb_tsd_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
};

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}
void put(const fs::path& p, const std::string& text) {
  std::ofstream out(p, std::ios::binary | std::ios::trunc);
  out << text;
}
bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0 || (std::isnan(a) && std::isnan(b)); }

// A two-marker, three-frame dataset whose numbers need all 17 digits (1/3, 0.1 + 0.2, a unit
// quaternion from an angle), one lost marker, forces, and unknown fields that must survive.
Dataset tiny_dataset(const fs::path& dir, std::vector<SampleData>* data) {
  fs::create_directories(dir / "meshes");
  put(dir / "meshes" / "tiny.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n");
  Dataset ds;
  ds.dir = dir.string();
  ds.name = "tiny";
  ds.provenance = "written by test_tsd";
  ds.license = "CC0-1.0";
  ds.camera.mm_per_px = 0.0634;
  ds.markers_rest_px = {Vec2(10.25, 20.5), Vec2(1.0 / 3.0, 7)};
  ds.indenters["tiny"] = TsdIndenter{"meshes/tiny.obj", {{"note", "tetrahedron"}}};
  ds.extra["recorded_by"] = "nobody";
  ds.sensor_extra["serial"] = 42;
  TsdSampleInfo s;
  s.id = "shr_00";
  s.motion = "shear";
  s.indenter = "tiny";
  s.split = "validation";
  s.dt_s = 0.1 + 0.2;
  s.has_forces = true;
  s.extra["operator"] = "x";
  ds.samples.push_back(s);

  SampleData d;
  const Quat q(Eigen::AngleAxisd(0.3, Vec3(1, 2, 3).normalized()));
  for (int k = 0; k < 3; ++k) {
    d.t_s.push_back(k * (0.1 + 0.2));
    d.p_EI.emplace_back(1.0 / 3.0 * k, -1e-9 * k, 0.0045 - 1e-4 * k / 7.0);
    d.q_EI.push_back(k == 0 ? Quat::Identity() : q);
    d.markers_px.push_back(
        {Vec2(0.1 * k, -0.7 / 3.0 * k), Vec2(k == 1 ? std::nan("") : 2.0 / 3.0, k == 1 ? std::nan("") : 1e-300)});
    d.forces_n.emplace_back(0.1 * k, 0.2, -1.0 / 7.0);
  }
  data->push_back(d);
  return ds;
}

// Writes a valid tiny dataset, replaces one file with `text`, and returns the error message of reading
// the whole dataset (empty when it reads).
std::string error_after_replacing(const std::string& file, const std::string& text) {
  TempDir t;
  std::vector<SampleData> data;
  const Dataset ds = tiny_dataset(t.path, &data);
  write_dataset(t.path.string(), ds, data);
  if (text.empty())
    fs::remove(t.path / file);
  else
    put(t.path / file, text);
  try {
    const Dataset back = read_dataset(t.path.string());
    read_sample(back, "shr_00");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

const std::string kPosesHeader = "frame,t_s,x_m,y_m,z_m,qw,qx,qy,qz\n";
const std::string kMarkersHeader = "frame,marker,du_px,dv_px\n";
// Three good pose rows (frames 0, 1, 2).
const std::string kGoodPoses = kPosesHeader +
                               "0,0,0,0,0.005,1,0,0,0\n1,0.02,0,0,0.004,1,0,0,0\n2,0.04,0,0,0.003,1,0,0,0\n";

std::string data_root() {
  const char* env = std::getenv("SHEARBENCH_DATA");
  return env && *env ? env : resolve_data_root();
}

}  // namespace

TEST_CASE("tsd: write then read reproduces every number bit for bit", "[tsd]") {
  TempDir t;
  std::vector<SampleData> data;
  const Dataset ds = tiny_dataset(t.path, &data);
  write_dataset(t.path.string(), ds, data);

  const Dataset back = read_dataset(t.path.string());
  CHECK(back.name == "tiny");
  CHECK(back.extra.at("recorded_by") == "nobody");
  CHECK(back.sensor_extra.at("serial") == 42);
  CHECK(back.indenters.at("tiny").extra.at("note") == "tetrahedron");
  REQUIRE(back.samples.size() == 1);
  CHECK(back.samples[0].extra.at("operator") == "x");
  CHECK(same_bits(back.samples[0].dt_s, 0.1 + 0.2));
  CHECK(same_bits(back.markers_rest_px[1].x(), 1.0 / 3.0));

  const SampleData d = read_sample(back, "shr_00");
  const SampleData& e = data[0];
  REQUIRE(d.frames() == 3);
  for (std::size_t k = 0; k < 3; ++k) {
    CHECK(same_bits(d.t_s[k], e.t_s[k]));
    for (int i = 0; i < 3; ++i) CHECK(same_bits(d.p_EI[k][i], e.p_EI[k][i]));
    for (int i = 0; i < 4; ++i) CHECK(same_bits(d.q_EI[k].coeffs()[i], e.q_EI[k].coeffs()[i]));
    for (int m = 0; m < 2; ++m)
      for (int i = 0; i < 2; ++i) CHECK(same_bits(d.markers_px[k][m][i], e.markers_px[k][m][i]));
    for (int i = 0; i < 3; ++i) CHECK(same_bits(d.forces_n[k][i], e.forces_n[k][i]));
  }
  CHECK(std::isnan(d.markers_px[1][1].x()));

  // Writing what was read gives the same bytes: the format is a fixed point of read/write.
  TempDir t2;
  fs::create_directories(t2.path / "meshes");
  fs::copy_file(t.path / "meshes" / "tiny.obj", t2.path / "meshes" / "tiny.obj");
  write_dataset(t2.path.string(), back, {d});
  for (const char* f : {"dataset.json", "shr_00/poses.csv", "shr_00/markers.csv", "shr_00/forces.csv"})
    CHECK(slurp(t.path / f) == slurp(t2.path / f));
  // No temporary files are left behind.
  for (const auto& entry : fs::recursive_directory_iterator(t.path))
    CHECK(entry.path().string().find(".tmp") == std::string::npos);
}

TEST_CASE("tsd: every malformed input names the file, line and column", "[tsd]") {
  using Catch::Matchers::Contains;
  SECTION("missing file") {
    CHECK_THAT(error_after_replacing("shr_00/poses.csv", ""), Contains("shr_00/poses.csv") && Contains("missing"));
  }
  SECTION("wrong header") {
    CHECK_THAT(error_after_replacing("shr_00/poses.csv", "frame,t,x,y,z,qw,qx,qy,qz\n0,0,0,0,0,1,0,0,0\n"),
               Contains("poses.csv:1:1: wrong header"));
  }
  SECTION("non-numeric pose value") {
    // Line 3 is frame 1; "1,0.02," is 7 characters, so x_m starts at column 8.
    CHECK_THAT(
        error_after_replacing("shr_00/poses.csv", kPosesHeader + "0,0,0,0,0.005,1,0,0,0\n1,0.02,abc,0,0.004,1,0,0,0\n"),
        Contains("poses.csv:3:8: x_m: expected a number"));
  }
  SECTION("NaN pose value") {
    // "0,0,0,0," is 8 characters: z_m at column 9.
    CHECK_THAT(error_after_replacing("shr_00/poses.csv", kPosesHeader + "0,0,0,0,nan,1,0,0,0\n"),
               Contains("poses.csv:2:9: z_m: value must be finite"));
  }
  SECTION("zero-norm quaternion") {
    // "0,0,0,0,0.005," is 14 characters: qw at column 15.
    CHECK_THAT(error_after_replacing("shr_00/poses.csv", kPosesHeader + "0,0,0,0,0.005,0,0,0,0\n"),
               Contains("poses.csv:2:15: quaternion has zero norm"));
  }
  SECTION("frame gap") {
    CHECK_THAT(
        error_after_replacing("shr_00/poses.csv", kPosesHeader + "0,0,0,0,0.005,1,0,0,0\n2,0.04,0,0,0.004,1,0,0,0\n"),
        Contains("poses.csv:3:1: frame gap"));
  }
  SECTION("frames out of order") {
    CHECK_THAT(
        error_after_replacing("shr_00/poses.csv", kPosesHeader + "0,0,0,0,0.005,1,0,0,0\n0,0.04,0,0,0.004,1,0,0,0\n"),
        Contains("poses.csv:3:1: frame 0 out of order"));
  }
  SECTION("wrong number of columns") {
    CHECK_THAT(error_after_replacing("shr_00/poses.csv", kPosesHeader + "0,0,0,0,0.005,1,0,0\n"),
               Contains("poses.csv:2:1: expected 9 columns, got 8"));
  }
  SECTION("marker index out of range") {
    // Two markers (0, 1): index 5 on line 3, column 3.
    CHECK_THAT(error_after_replacing("shr_00/markers.csv", kMarkersHeader + "0,0,0,0\n0,5,0,0\n"),
               Contains("markers.csv:3:3: marker index 5 out of range"));
  }
  SECTION("missing marker row") {
    // Frame 0 has only marker 0; the problem shows when frame 1 starts on line 3.
    CHECK_THAT(error_after_replacing("shr_00/markers.csv", kMarkersHeader + "0,0,0,0\n1,0,0,0\n1,1,0,0\n"),
               Contains("markers.csv:3:1: frame 0 has 1 of 2 marker rows (marker 1 missing"));
  }
  SECTION("markers out of order") {
    CHECK_THAT(
        error_after_replacing("shr_00/markers.csv", kMarkersHeader + "0,0,0,0\n0,1,0,0\n1,0,0,0\n1,1,0,0\n0,0,0,0\n"),
        Contains("markers.csv:6:1: frame 0 out of order"));
  }
  SECTION("markers end early") {
    CHECK_THAT(error_after_replacing("shr_00/markers.csv", kMarkersHeader + "0,0,0,0\n0,1,0,0\n"),
               Contains("markers.csv:3:1: markers end at frame 0 but poses.csv has 3 frames"));
  }
  SECTION("half-lost marker") {
    CHECK_THAT(error_after_replacing("shr_00/markers.csv", kMarkersHeader + "0,0,nan,0\n"),
               Contains("markers.csv:2:5: a lost marker must be nan in both"));
  }
  SECTION("unknown motion") {
    TempDir t;
    std::vector<SampleData> data;
    Dataset ds = tiny_dataset(t.path, &data);
    write_dataset(t.path.string(), ds, data);
    std::string json = slurp(t.path / "dataset.json");
    json.replace(json.find("\"shear\""), 7, "\"shove\"");
    put(t.path / "dataset.json", json);
    CHECK_THROWS_WITH(read_dataset(t.path.string()),
                      Contains("dataset.json: /samples/0/motion: unknown motion 'shove'"));
  }
  SECTION("unknown split") {
    TempDir t;
    std::vector<SampleData> data;
    Dataset ds = tiny_dataset(t.path, &data);
    write_dataset(t.path.string(), ds, data);
    std::string json = slurp(t.path / "dataset.json");
    json.replace(json.find("\"validation\""), 12, "\"test\"");
    put(t.path / "dataset.json", json);
    CHECK_THROWS_WITH(read_dataset(t.path.string()), Contains("dataset.json: /samples/0/split: unknown split 'test'"));
  }
  SECTION("referenced mesh does not exist") {
    TempDir t;
    std::vector<SampleData> data;
    Dataset ds = tiny_dataset(t.path, &data);
    write_dataset(t.path.string(), ds, data);
    fs::remove(t.path / "meshes" / "tiny.obj");
    CHECK_THROWS_WITH(read_dataset(t.path.string()),
                      Contains("dataset.json: /indenters/tiny/mesh: mesh file 'meshes/tiny.obj' not found"));
  }
  SECTION("JSON syntax error") {
    TempDir t;
    put(t.path / "dataset.json", "{\n  \"format\": \"tsd/1\",\n  \"name\": ]\n}\n");
    // The stray ']' is on line 3, column 11.
    CHECK_THROWS_WITH(read_dataset(t.path.string()), Contains("dataset.json:3:11: invalid JSON"));
  }
}

TEST_CASE("tsd: a non-unit quaternion is normalised with a warning", "[tsd]") {
  TempDir t;
  std::vector<SampleData> data;
  const Dataset ds = tiny_dataset(t.path, &data);
  write_dataset(t.path.string(), ds, data);
  put(t.path / "shr_00" / "poses.csv",
      kPosesHeader + "0,0,0,0,0.005,2,0,0,0\n1,0.02,0,0,0.004,1,0,0,0\n2,0.04,0,0,0.003,1,0,0,0\n");
  Warnings w;
  const SampleData d = read_sample(read_dataset(t.path.string()), "shr_00", &w);
  // (2, 0, 0, 0) / 2 = identity.
  CHECK(d.q_EI[0].w() == 1.0);
  REQUIRE(w.messages.size() == 1);
  CHECK_THAT(w.messages[0], Catch::Matchers::Contains("poses.csv:2:"));
}

TEST_CASE("tsd: reads twin_sphere35 from the data root", "[tsd]") {
  const fs::path dir = fs::path(data_root()) / "twin" / "twin_sphere35";
  if (!fs::exists(dir / "dataset.json")) FAIL("twin_sphere35 not found at " << dir << " (set SHEARBENCH_DATA)");
  const Dataset ds = read_dataset(dir.string());
  CHECK(ds.samples.size() == 40);
  CHECK(ds.markers_rest_px.size() == kMiniMarkers);
  CHECK(ds.markers_rest_px[0] == Vec2(27.5, 20.5));  // FORMAT.md grid: first marker 4 pitches left, 3 up
  const SampleData d = read_sample(ds, "dil_00");
  // First row of dil_00/poses.csv: 0,0.000,-0.004497363,-0.000634689,0.017700000,1,0,0,0
  CHECK(d.t_s[0] == 0.0);
  CHECK(d.p_EI[0] == Vec3(-0.004497363, -0.000634689, 0.017700000));
  CHECK(d.q_EI[0].w() == 1.0);
  CHECK(d.q_EI[0].vec() == Vec3::Zero());
  CHECK(d.frames() == 41);                            // 42 lines with the header
  CHECK(d.markers_px[0][0] == Vec2(0.1035, 0.0801));  // first row of markers.csv
  CHECK(d.forces_n.size() == 41);

  // Every sample loads (the timing is reported by `shearbench check`).
  std::size_t frames = 0;
  for (const auto& s : ds.samples) frames += read_sample(ds, s.id).frames();
  CHECK(frames > 40);
}

TEST_CASE("a binary header is quoted as printable text in the error", "[tsd]") {
  // Bytes 0x00 0xff and a newline-free run of 200 'a': the message shows \x00\xff, then cuts after 80 chars.
  CHECK(sb::printable(std::string("ab\0\xff", 4)) == "ab\\x00\\xff");
  CHECK(sb::printable(std::string(200, 'a')) == std::string(80, 'a') + "...");
}

TEST_CASE("tsd: a pinhole camera, a spherical-cap gel and pins at depth round-trip; a classic block is unchanged",
          "[tsd][sensor]") {
  TempDir t;
  std::vector<SampleData> data;
  Dataset ds = tiny_dataset(t.path, &data);
  // The classic (orthographic, flat, depth 0) block has exactly the keys it always had.
  const nlohmann::ordered_json classic = dataset_to_json(ds)["sensor"];
  CHECK(classic["camera"].dump() == R"({"model":"orthographic","mm_per_px":0.0634,"principal_px":[159.5,119.5]})");
  CHECK_FALSE(classic.contains("markers_depth_m"));
  CHECK(classic["gel"].size() == 3);

  ds.camera.model = CameraModel::kPinhole;
  ds.camera.focal_px = 1.0 / 3.0 * 1000;
  ds.camera.distance_m = 0.03;
  ds.camera.k1 = -0.1 - 0.2;
  ds.gel.surface = "spherical_cap";
  ds.gel.radius_m = 0.02;
  ds.gel.footprint_radius_m = 0.0175;
  ds.gel.thickness_m = 0.025;
  ds.gel.markers_depth_m = 0.0035;
  write_dataset(t.path.string(), ds, data);
  const Dataset back = read_dataset(t.path.string());
  CHECK(back.camera.pinhole());
  CHECK(same_bits(back.camera.focal_px, ds.camera.focal_px));
  CHECK(same_bits(back.camera.distance_m, 0.03));
  CHECK(same_bits(back.camera.k1, -0.1 - 0.2));
  CHECK(back.gel.surface == "spherical_cap");
  CHECK(same_bits(back.gel.radius_m, 0.02));
  CHECK(same_bits(back.gel.footprint_radius_m, 0.0175));
  CHECK(same_bits(back.gel.markers_depth_m, 0.0035));
  CHECK_FALSE(back.sensor_extra.contains("markers_depth_m"));
}

TEST_CASE("tsd: bad camera, cap and depth values name the file and the JSON pointer", "[tsd][sensor]") {
  using Catch::Matchers::Contains;
  TempDir t;
  std::vector<SampleData> data;
  const Dataset ds = tiny_dataset(t.path, &data);
  write_dataset(t.path.string(), ds, data);
  const nlohmann::json good = nlohmann::json::parse(slurp(t.path / "dataset.json"));
  auto error_of = [&](const std::function<void(nlohmann::json&)>& edit) -> std::string {
    nlohmann::json j = good;
    edit(j["sensor"]);
    try {
      parse_dataset_json(j, "x/dataset.json", t.path.string());
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  };
  auto pinhole = [](nlohmann::json& s) {
    s["camera"] = {{"model", "pinhole"}, {"focal_px", 300}, {"principal_px", {320, 240}}, {"distance_m", 0.03}};
  };
  auto capped = [](nlohmann::json& s) {
    s["gel"] = {{"size_m", {0.04, 0.04}},
                {"thickness_m", 0.025},
                {"surface", "spherical_cap"},
                {"radius_m", 0.02},
                {"footprint_radius_m", 0.0175}};
  };
  CHECK(error_of([&](nlohmann::json& s) {
          pinhole(s);
          capped(s);
          s["markers_depth_m"] = 0.003;
        }).empty());
  CHECK_THAT(error_of([](nlohmann::json& s) { s["camera"]["model"] = "fisheye"; }),
             Contains("x/dataset.json: /sensor/camera/model: unknown camera model 'fisheye'"));
  CHECK_THAT(error_of([&](nlohmann::json& s) {
               pinhole(s);
               s["camera"].erase("focal_px");
             }),
             Contains("x/dataset.json: /sensor/camera") && Contains("focal_px"));
  CHECK_THAT(error_of([&](nlohmann::json& s) {
               pinhole(s);
               s["camera"]["distance_m"] = -1;
             }),
             Contains("/sensor/camera/distance_m: expected a positive number"));
  CHECK_THAT(error_of([&](nlohmann::json& s) {
               pinhole(s);
               s["camera"]["mm_per_px"] = 0.1;
             }),
             Contains("/sensor/camera/mm_per_px"));
  CHECK_THAT(error_of([](nlohmann::json& s) { s["camera"]["k1"] = 0.1; }),
             Contains("/sensor/camera/k1: only a pinhole camera has this key"));
  CHECK_THAT(error_of([&](nlohmann::json& s) {
               capped(s);
               s["gel"]["footprint_radius_m"] = 0.03;
             }),
             Contains("/sensor/gel/footprint_radius_m: must not exceed radius_m"));
  CHECK_THAT(error_of([&](nlohmann::json& s) {
               capped(s);
               s["gel"]["thickness_m"] = 0.001;
             }),
             Contains("/sensor/gel/thickness_m: must exceed the cap height"));
  CHECK_THAT(error_of([&](nlohmann::json& s) {
               capped(s);
               s["gel"].erase("radius_m");
             }),
             Contains("/sensor/gel") && Contains("radius_m"));
  CHECK_THAT(error_of([](nlohmann::json& s) { s["gel"]["radius_m"] = 0.02; }),
             Contains("/sensor/gel/radius_m: only a spherical_cap gel has this key"));
  CHECK_THAT(error_of([](nlohmann::json& s) { s["markers_depth_m"] = -0.001; }),
             Contains("x/dataset.json: /sensor/markers_depth_m: must be >= 0"));
  CHECK_THAT(error_of([&](nlohmann::json& s) {
               capped(s);
               s["markers_depth_m"] = 0.02;
             }),
             Contains("/sensor/markers_depth_m: must be smaller than the gel's radius_m"));
}

TEST_CASE("tsd: a calibration list reassigns the splits; with a validation list the other samples go", "[tsd]") {
  Dataset ds;
  ds.name = "five";
  for (const char* id : {"a", "b", "c", "d", "e"}) {
    TsdSampleInfo s;
    s.id = id;
    s.split = "validation";
    ds.samples.push_back(s);
  }
  const auto ids_of = [](const Dataset& d, const std::string& split) {
    std::string out;
    for (const auto& s : d.samples)
      if (s.split == split) out += s.id;
    return out;
  };
  SECTION("calibration list only: every other sample validates") {
    assign_calibration_split(ds, {"b", "d"}, "--calibration");
    CHECK(ids_of(ds, "calibration") == "bd");
    CHECK(ids_of(ds, "validation") == "ace");
  }
  SECTION("both lists: c and e are in neither and are dropped, the order kept") {
    assign_calibration_split(ds, {"b"}, "--calibration", {"a", "d"});
    CHECK(ds.samples.size() == 3);
    CHECK(ids_of(ds, "calibration") == "b");
    CHECK(ids_of(ds, "validation") == "ad");
  }
  SECTION("an id the dataset lacks names the option, in either list") {
    CHECK_THROWS_WITH(assign_calibration_split(ds, {"b"}, "validation_samples", {"z"}),
                      Catch::Contains("validation_samples") && Catch::Contains("no sample 'z'"));
    CHECK_THROWS_WITH(assign_calibration_split(ds, {"y"}, "--calibration"), Catch::Contains("no sample 'y'"));
  }
}

}  // namespace test_tsd
