// The TacTip sensor description and what the data identify of it (core/sensor/tactip_sensor.hpp,
// core/sensor/tactip_identify.hpp, read from a file by core/data/tactip_sensor.hpp), and the import's inputs as users
// have them.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>

#include "core/base/data_root.hpp"
#include "core/base/error.hpp"
#include "core/data/importers.hpp"
#include "core/data/tactip_sensor.hpp"
#include "core/data/tsd.hpp"
#include "core/sensor/tactip_identify.hpp"
#include "tests/temp_path.hpp"

namespace test_tactip_sensor {

using namespace sb;
namespace fs = std::filesystem;

TEST_CASE("image-from-tool rotation: a known rotation and gain back, and a mirror told apart", "[tactip_sensor]") {
  // Responses m = g Rz(a) s exactly, g = 2 px/mm, a = 30 deg, on presses 1..4 mm with slides round the circle of
  // 3 mm: the fit returns a and g to rounding (tolerance 1e-9) with no residual; the mirrored model
  // m = g Rz(a) diag(1, -1) s is found as mirrored.
  constexpr double kTol = 1e-9;
  const double g = 2.0, a = 30.0 * M_PI / 180.0;
  for (bool mirrored : {false, true}) {
    std::vector<ShearResponse> rs;
    for (int k = 0; k < 40; ++k) {
      ShearResponse r;
      r.depth_mm = 1.0 + 3.0 * k / 39.0;
      const double phi = 2 * M_PI * k / 40.0;
      r.shear_mm = Vec2(3 * std::cos(phi), 3 * std::sin(phi));
      const Vec2 s = mirrored ? Vec2(r.shear_mm.x(), -r.shear_mm.y()) : r.shear_mm;
      r.response_px = g * (Eigen::Rotation2Dd(a) * s);
      r.tracked = true;
      rs.push_back(r);
    }
    const ImageFromTool f = identify_image_from_tool(rs, "test");
    CHECK(f.mirrored == mirrored);
    CHECK(f.angle_rad == Approx(a).margin(kTol));
    CHECK(f.gain_px_per_mm == Approx(g).margin(kTol));
    CHECK((mirrored ? f.mirrored_rms_px : f.rms_px) < kTol);
    CHECK((mirrored ? f.rms_px : f.mirrored_rms_px) > 1.0);  // the other model does not fit
    // Only the shallow half is used: depth <= the median, the upper middle one (the 21st of 40).
    CHECK(f.samples == 21);
  }
  SECTION("too few slides is an error naming the place and the remedy") {
    std::vector<ShearResponse> rs(3);
    for (auto& r : rs) r.tracked = true;
    CHECK_THROWS_WITH(identify_image_from_tool(rs, "x/targets.csv"),
                      Catch::Contains("x/targets.csv") && Catch::Contains("--sensor"));
  }
}

TEST_CASE("contact onset: the line of the moving fraction in depth meets zero at the onset", "[tactip_sensor]") {
  // moving_fraction = 0.1 (d - 1.5) above d = 1.5 mm, 0 below, on presses 0.5 .. 5 mm with a full slide: the
  // shallowest third of the pressed ones lie on the line, so the intercept is 1.5 to rounding; the presses
  // below it move no pin, so the onset is identified.
  constexpr double kTol = 1e-9;
  std::vector<ShearResponse> rs;
  for (int k = 0; k < 91; ++k) {
    ShearResponse r;
    r.depth_mm = 0.5 + 0.05 * k;
    r.shear_mm = Vec2(3, 0);
    r.tracked = true;
    r.moving_fraction = std::max(0.0, 0.1 * (r.depth_mm - 1.5));
    rs.push_back(r);
  }
  ContactOnset on = identify_contact_onset(rs);
  CHECK(on.identified);
  CHECK(on.extrapolated_mm == Approx(1.5).margin(kTol));
  CHECK(on.out_of_contact == 21);  // 0.5 .. 1.5 mm
  SECTION("every press touching: extrapolated, not identified") {
    rs.erase(std::remove_if(rs.begin(), rs.end(), [](const auto& r) { return r.moving_fraction == 0; }), rs.end());
    on = identify_contact_onset(rs);
    CHECK_FALSE(on.identified);
    CHECK(on.extrapolated_mm == Approx(1.5).margin(kTol));
  }
}

TEST_CASE("a --sensor file: values given over the defaults, bad ones named by file and pointer", "[tactip_sensor]") {
  const fs::path dir = sbtest::temp_path("sb_test_tactip_sensor_file");
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string f = (dir / "sensor.json").string();
  { std::ofstream(f) << R"({"dome_radius_mm": 22.5, "pin_depth_mm": {"value": 2.5, "source": "datasheet"}})"; }
  TactipSensor s = tactip_standard_defaults();
  read_tactip_sensor_file(f, &s);
  CHECK(s.dome_radius_mm.value == 22.5);
  CHECK(s.dome_radius_mm.source == SensorValueSource::kGiven);
  CHECK(s.pin_depth_mm.value == 2.5);
  CHECK(s.ring_pitch_deg.source == SensorValueSource::kDefault);
  // The dataset's own description reads back: every value becomes given.
  TactipSensor back = tactip_standard_defaults();
  apply_tactip_sensor_json(nlohmann::json::parse(to_json(s).dump()), "d.json", &back);
  CHECK(back.dome_radius_mm.value == 22.5);
  CHECK(back.k1.source == SensorValueSource::kGiven);
  { std::ofstream(f) << R"({"dome_radius": 20})"; }
  CHECK_THROWS_WITH(read_tactip_sensor_file(f, &s),
                    Catch::Contains("sensor.json") && Catch::Contains("/dome_radius") && Catch::Contains("unknown"));
  { std::ofstream(f) << R"({"focal_px": -3})"; }
  CHECK_THROWS_WITH(read_tactip_sensor_file(f, &s), Catch::Contains("/focal_px"));
  fs::remove_all(dir);
}

fs::path tactip_raw() {
  const char* env = std::getenv("SHEARBENCH_DATA");
  const fs::path p = fs::path(env && *env ? std::string(env) : resolve_data_root()) / "raw" / "tactip_shear";
  if (!fs::exists(p)) FAIL("test data missing: " << p << " (set SHEARBENCH_DATA)");
  return p;
}

// A folder with the shipped reference and the first rows of each split, targets.csv written by `write`.
fs::path small_tactip_copy(const std::string& name, int rows, const std::function<void(const fs::path&)>& edit) {
  const fs::path src = tactip_raw();
  const fs::path dir = sbtest::temp_path(name);
  fs::remove_all(dir);
  for (const char* split : {"calibration", "validation"}) {
    fs::create_directories(dir / split / "images");
    std::ifstream in(src / split / "targets.csv");
    std::ofstream out(dir / split / "targets.csv");
    std::string line;
    for (int k = 0; k <= rows && std::getline(in, line); ++k) {
      out << line << "\n";
      if (k == 0) continue;
      const std::string image = line.substr(0, line.find(','));
      fs::copy_file(src / split / "images" / image, dir / split / "images" / image);
    }
    fs::copy_file(src / split / "images" / "image_0.png", dir / split / "images" / "image_0.png");
  }
  edit(dir);
  return dir;
}

TEST_CASE("targets.csv as users save it: CRLF, a BOM, reordered and extra columns, a malformed side file",
          "[import][tactip_sensor]") {
  // The same three rows per split, once as shipped and once with CRLF line ends, a UTF-8 BOM, the columns
  // reversed with one more, and env_params.json cut short the way the source's is ("]]}"): the import reads
  // the same samples (side files are not read) with the same pins.
  TactipImportOptions o;
  o.max_samples_per_split = 3;
  o.use_prior = false;
  const fs::path plain = small_tactip_copy("sb_test_tactip_plain", 3, [](const fs::path&) {});
  const fs::path messy = small_tactip_copy("sb_test_tactip_messy", 3, [](const fs::path& dir) {
    for (const char* split : {"calibration", "validation"}) {
      std::ifstream in(dir / split / "targets.csv");
      std::vector<std::vector<std::string>> rows;
      for (std::string line; std::getline(in, line);) {
        std::vector<std::string> c;
        std::stringstream ss(line);
        for (std::string x; std::getline(ss, x, ',');) c.push_back(x);
        std::reverse(c.begin(), c.end());
        c.push_back(rows.empty() ? "operator" : "\"me\"");
        rows.push_back(c);
      }
      in.close();
      std::ofstream out(dir / split / "targets.csv", std::ios::binary);
      out << "\xEF\xBB\xBF";
      for (const auto& r : rows) {
        for (std::size_t k = 0; k < r.size(); ++k) out << (k ? "," : "") << r[k];
        out << "\r\n";
      }
      std::ofstream(dir / split / "env_params.json") << R"({"robot": "cr", "work_frame": [[20, -475, 100]]})"
                                                     << "]]}";
    }
  });
  // Too few samples for the rotation fit: it is given, as a user would from an earlier import.
  const fs::path sensor = plain / "sensor.json";
  std::ofstream(sensor) << R"({"image_from_tool_deg": -162})";
  o.sensor_file = sensor.string();
  import_tactip_shear(plain.string(), (plain / "out").string(), o);
  import_tactip_shear(messy.string(), (messy / "out").string(), o);
  const Dataset a = read_dataset((plain / "out").string()), b = read_dataset((messy / "out").string());
  REQUIRE(a.samples.size() == b.samples.size());
  for (std::size_t k = 0; k < a.samples.size(); ++k) CHECK(a.samples[k].id == b.samples[k].id);
  CHECK(a.markers_rest_px.size() == b.markers_rest_px.size());
  const SampleData sa = read_sample(a, a.samples[1].id), sb_ = read_sample(b, b.samples[1].id);
  CHECK(sa.p_EI.back() == sb_.p_EI.back());
  CHECK(sa.markers_px.back().size() == sb_.markers_px.back().size());
  fs::remove_all(plain);
  fs::remove_all(messy);
}

}  // namespace test_tactip_sensor
