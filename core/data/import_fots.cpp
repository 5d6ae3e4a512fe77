// The FOTS marker calibration pair importer (import_fots.hpp).
#include "core/data/import_fots.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include "core/base/error.hpp"
#include "core/base/format.hpp"
#include "core/base/median.hpp"
#include "core/data/obj_writers.hpp"
#include "core/data/sphere_contact.hpp"
#include "core/sensor/camera.hpp"

namespace fs = std::filesystem;

namespace sb {

namespace {

struct FotsCsv {
  std::vector<Vec2> rest, disp;
};

FotsCsv read_fots_csv(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path, "cannot open");
  std::string line;
  std::getline(in, line);
  if (line.rfind("Mx,My,dx,dy", 0) != 0) throw InputError(path, 1, 1, "expected header Mx,My,dx,dy");
  FotsCsv c;
  int lineno = 1;
  while (std::getline(in, line)) {
    ++lineno;
    if (line.empty() || line == "\r") continue;
    double mx, my, dx, dy;
    if (std::sscanf(line.c_str(), "%lf,%lf,%lf,%lf", &mx, &my, &dx, &dy) != 4)
      throw InputError(path, lineno, 1, "expected four numbers Mx,My,dx,dy");
    c.rest.emplace_back(mx, my);
    c.disp.emplace_back(dx, dy);
  }
  if (c.rest.empty()) throw InputError(path, "no markers");
  return c;
}

double pitch_of(const std::vector<Vec2>& pts) {
  std::vector<double> nn;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t j = 0; j < pts.size(); ++j)
      if (i != j) best = std::min(best, (pts[i] - pts[j]).norm());
    nn.push_back(best);
  }
  return median(nn);
}

// Scale: marker_calib.py uses 0.0266 mm/px on images downsampled by 2 (ball_r = 3 / (0.0266*2)), i.e.
// 0.0532 mm/px; params.py's 19.58 px/mm is 0.0511 mm/px. We write 0.0532 and carry the 4 % spread.
constexpr double kMmPerPx = 0.0532, kMmPerPxAlt = 1.0 / 19.58;
constexpr double kFotsRadiiMm[2] = {2.35, 3.0};  // params.py diameter 4.70 mm; marker_calib.py radius 3 mm
constexpr double kFotsSphereRadiusM = 0.003;
// What the pair is, how its poses were estimated, and the estimates (the tsd/1 provenance text).
std::string fots_provenance(std::size_t markers, double pitch, const SphereContactEstimate& ep,
                            const SphereContactEstimate& es) {
  std::ostringstream prov;
  prov << "FOTS marker calibration pair from Rancho-zhao/FOTS (MIT), marker_calib/data/, see "
          "raw/fots_marker_calib/SOURCE.md. markers_rest_px = the CSV's Mx,My (integer px, "
       << markers << " markers, 11 cols x 9 rows, pitch " << format_number(pitch, "%.1f")
       << " px); each sample has frame 0 = rest (zero displacement, written by us) and frame 1 = the CSV's dx,dy "
          "(integers: 1 px quantisation). Scale 0.0532 mm/px (marker_calib.py: 0.0266 mm/px x 2 for its "
          "downsampled images; params.py's 19.58 px/mm = 0.0511 mm/px differs by 4 %). "
       << kImportAxisNote
       << " background_nocontact.png is not used: it is a 240x320 (portrait) frame without markers from another "
          "sensor crop, so an image difference is not meaningful. POSE ESTIMATE (pose_known false), from the marker "
          "field only: far-field drift = median displacement (removed); contact centre = |d|-weighted centroid of "
          "markers above half the peak |d|; contact radius a = radius of the peak mean radial displacement "
          "(ring width pitch/2), uncertainty +-pitch/2; depth d = R - sqrt(R^2 - a^2); tangential travel = mean "
          "displacement inside a (a lower bound if the contact slipped). The shear image's radial ring is swamped by "
          "the "
          "tangential field, so its contact radius is taken from the press estimate (same press, then a sideways "
          "move). ";
  auto describe = [&](const char* what, const SphereContactEstimate& e) {
    prov << what << ": centre (" << format_number(e.centre_px.x(), "%.1f") << ", "
         << format_number(e.centre_px.y(), "%.1f") << ") px, drift (" << format_number(e.drift_px.x(), "%.2f") << ", "
         << format_number(e.drift_px.y(), "%.2f") << ") px, a = " << format_number(e.a_px, "%.1f") << " +- "
         << format_number(e.a_sigma_px, "%.1f") << " px = " << format_number(e.a_px * kMmPerPx, "%.2f") << " +- "
         << format_number(e.a_sigma_px * kMmPerPx, "%.2f") << " mm";
    for (double R : kFotsRadiiMm) {
      const double a = e.a_px * kMmPerPx, s = e.a_sigma_px * kMmPerPx;
      prov << "; R = " << R << " mm: d = " << format_number(sphere_depth_from_contact_radius(R, a), "%.3f")
           << " mm (range " << format_number(sphere_depth_from_contact_radius(R, std::max(0.0, a - s)), "%.3f")
           << " .. " << format_number(sphere_depth_from_contact_radius(R, a + s), "%.3f") << ", nan = a exceeds R)";
    }
    prov << "; travel (" << format_number(e.travel_px.x(), "%.2f") << ", " << format_number(e.travel_px.y(), "%.2f")
         << ") +- " << format_number(e.travel_sigma_px, "%.2f") << " px = ("
         << format_number(e.travel_px.x() * kMmPerPx, "%.3f") << ", "
         << format_number(e.travel_px.y() * kMmPerPx, "%.3f") << ") mm over " << e.markers_inside << " markers. ";
  };
  describe("press", ep);
  describe("shear", es);
  prov << "poses.csv: the sphere (indenter sphere_r3, R = 3 mm, marker_calib.py) centred over the estimated "
          "contact centre, frame 0 touching the surface (z = R), frame 1 at z = R - d; for shear, frame 1 is also "
          "moved by the estimated travel. Scale alternative "
       << format_number(kMmPerPxAlt, "%.4f")
       << " mm/px changes "
          "lengths by 4 %.";

  return prov.str();
}

// One state of the pair: rest then the CSV's field, the sphere posed over the estimated contact.
TsdSampleOut fots_sample(const char* id, const FotsCsv& c, const SphereContactEstimate& e, bool sheared,
                         const Camera& cam) {
  TsdSampleOut s;
  s.id = id;
  s.motion = sheared ? "shear" : "dilation";
  s.indenter = "sphere_r3";
  s.dt_s = 1.0;  // two states, no timing in the source
  s.disp_px = {std::vector<Vec2>(c.rest.size(), Vec2::Zero()), c.disp};
  const Vec2 p0 = cam.E_from_px(e.centre_px - (sheared ? e.travel_px : Vec2::Zero()));
  const Vec2 p1 = cam.E_from_px(e.centre_px);
  const double depth = sphere_depth_from_contact_radius(kFotsSphereRadiusM * 1e3, e.a_px * kMmPerPx) * 1e-3;
  s.X_EI = {
      make_pose(Vec3(p0.x(), p0.y(), kFotsSphereRadiusM), Quat::Identity()),
      make_pose(Vec3(p1.x(), p1.y(), kFotsSphereRadiusM - (std::isfinite(depth) ? depth : 0.0)), Quat::Identity())};
  nlohmann::json est;
  est["contact_centre_px"] = {e.centre_px.x(), e.centre_px.y()};
  est["contact_radius_px"] = e.a_px;
  est["contact_radius_sigma_px"] = e.a_sigma_px;
  est["travel_px"] = {e.travel_px.x(), e.travel_px.y()};
  est["travel_sigma_px"] = e.travel_sigma_px;
  for (double Rm : kFotsRadiiMm)
    est["depth_mm_for_R_mm"][format_number(Rm, "%.2f")] = sphere_depth_from_contact_radius(Rm, e.a_px * kMmPerPx);
  s.extra = {{"pose_estimate", est}};
  return s;
}

}  // namespace

ImportReport import_fots(const std::string& in_dir, const std::string& out_dir) {
  require_input_dir(in_dir);
  const FotsCsv press = read_fots_csv((fs::path(in_dir) / "press.csv").string());
  const FotsCsv shear = read_fots_csv((fs::path(in_dir) / "shear.csv").string());
  if (press.rest.size() != shear.rest.size())
    throw InputError((fs::path(in_dir) / "shear.csv").string(), "marker count differs from press.csv");
  for (std::size_t i = 0; i < press.rest.size(); ++i)
    if ((press.rest[i] - shear.rest[i]).norm() > 0.5)
      throw InputError((fs::path(in_dir) / "shear.csv").string(), int(i) + 2, 1,
                       "rest position differs from press.csv");

  const double pitch = pitch_of(press.rest);
  const SphereContactEstimate ep = estimate_sphere_contact(press.rest, press.disp, pitch);
  // In the shear image the tangential field swamps the radial ring, so its own radius estimate is not
  // meaningful: the shear state reuses the press radius (same press, then a sideways move) and averages the
  // travel over the markers inside that radius around the shear field's centre.
  SphereContactEstimate es = estimate_sphere_contact(shear.rest, shear.disp, pitch);
  es = estimate_sphere_contact_with_radius(shear.rest, shear.disp, es.centre_px, ep.a_px, ep.a_sigma_px);

  TsdDatasetOut ds;
  ds.name = "fots_marker_calib";
  ds.kind = "real";
  ds.license = "MIT";
  ds.mm_per_px = kMmPerPx;
  ds.principal_px = Vec2(159.5, 119.5);
  ds.markers_rest_px = press.rest;
  ds.indenters = {{"sphere_r3", {{"mesh", "meshes/sphere_r3.obj"}}}};
  ds.mesh_files = {{"meshes/sphere_r3.obj", sphere_obj(0.003)}};
  ds.provenance = fots_provenance(press.rest.size(), pitch, ep, es);
  Camera cam;
  cam.mm_per_px = kMmPerPx;
  cam.principal_px = ds.principal_px;
  ds.samples = {fots_sample("press", press, ep, false, cam), fots_sample("shear", shear, es, true, cam)};
  write_tsd_dataset(ds, out_dir);
  ImportReport report;
  report.datasets.push_back(out_dir);
  report.lines.push_back("fots: press a = " + format_number(ep.a_px, "%.1f") +
                         " px, shear a = " + format_number(es.a_px, "%.1f") + " px, shear travel (" +
                         format_number(es.travel_px.x(), "%.2f") + ", " + format_number(es.travel_px.y(), "%.2f") +
                         ") px");
  return report;
}

}  // namespace sb
