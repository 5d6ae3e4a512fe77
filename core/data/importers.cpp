#include "core/data/importers.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <numeric>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>
#include <sstream>

#include "core/base/atomic_write.hpp"
#include "core/base/error.hpp"
#include "core/base/format.hpp"
#include "core/base/median.hpp"
#include "core/base/numbers.hpp"
#include "core/data/tactip_sensor.hpp"
#include "core/sensor/camera.hpp"
#include "core/sensor/sensor.hpp"
#include "core/sensor/tactip_geometry_fit.hpp"
#include "core/tracking/lattice_check.hpp"
#include "core/tracking/pin_field_prior.hpp"

namespace fs = std::filesystem;

namespace sb {
namespace {

constexpr double kDefaultFps = 25.0;
constexpr const char* kUnknownContact =
    "unknown_contact";  // GelSight Mini recordings (SOURCE.md), used when the file has none
const char* kAxisNote =
    "Axes: the camera looks along +z_E from inside the gel, so image u (right), v (down) are x_E, y_E of a "
    "right-handed E with +z out of the gel; no mirroring applied.";
const char* kPoseNote =
    "Pose unknown (pose_known false): poses.csv holds identity placeholder rows only so that every sample "
    "has one row per frame; they are not measurements. The sample's indenter 'unknown_contact' is a labelled "
    "1 mm sphere proxy (tsd/1 requires a mesh), not the real contact.";

double video_dt_s(const std::string& path) {
  cv::VideoCapture cap(path, cv::CAP_FFMPEG);  // FFmpeg only: no GStreamer or image-sequence guesses
  const double fps = cap.isOpened() ? cap.get(cv::CAP_PROP_FPS) : 0.0;
  return 1.0 / (fps > 1.0 && fps < 1000.0 ? fps : kDefaultFps);
}

std::string track_summary(const TrackResult& r) {
  std::ostringstream o;
  o << r.frames() << " frames, " << r.markers() << " markers";
  if (r.grid_rows)
    o << " (grid " << r.grid_rows << " rows x " << r.grid_cols << " cols)";
  else
    o << " (irregular grid at rest)";
  o << ", pitch " << format_number(r.pitch_px, "%.2f") << " px, lost " << format_number(r.lost_fraction(), "%.4f")
    << " of marker-frames";
  return o.str();
}

// Tracks one video into its own dataset directory; a video that cannot be read is reported, not fatal.
void import_video(const std::string& video, const std::string& out, const std::string& name, const TrackerOptions& opts,
                  double mm_per_px, const std::string& origin, const std::string& license, nlohmann::json extra,
                  ImportReport& report, bool keep_frames) {
  TrackResult r;
  try {
    r = track_video(video, opts);
  } catch (const InputError& e) {
    report.lines.push_back(name + ": skipped, " + e.what());
    return;
  }
  std::string note = origin + " Tracked with shearbench's marker tracker (rest = median of the first " +
                     std::to_string(opts.rest_frames) + " frames, grid auto-detected: " + track_summary(r) +
                     "). Scale " + format_number(mm_per_px, "%.4f") +
                     " mm/px (vendor README), principal point the image centre. " + kAxisNote + " " + kPoseNote;
  for (const auto& w : r.warnings) note += " Tracker warning: " + w + ".";
  TsdDatasetOut ds = dataset_from_track(r, name, name, video_dt_s(video), mm_per_px, note);
  ds.license = license;
  ds.samples.front().extra = std::move(extra);
  if (keep_frames) {
    std::vector<cv::Mat> frames = read_video_frames(video);
    frames.resize(std::min<std::size_t>(frames.size(), static_cast<std::size_t>(r.frames())));
    if (frames.size() == static_cast<std::size_t>(r.frames()))
      ds.samples.front().frames = std::move(frames);
    else
      report.lines.push_back(name + ": frames not stored (decoded " + std::to_string(frames.size()) + " of " +
                             std::to_string(r.frames()) + ")");
  }
  write_tsd_dataset(ds, out);
  report.datasets.push_back(out);
  report.lines.push_back(name + ": " + track_summary(r));
}

void require_dir(const std::string& dir) {
  if (!fs::is_directory(dir)) throw InputError(dir, "input directory not found");
}

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

}  // namespace

TsdDatasetOut dataset_from_track(const TrackResult& track, const std::string& name, const std::string& sample_id,
                                 double dt_s, double mm_per_px, const std::string& source_note) {
  TsdDatasetOut ds;
  ds.name = name;
  ds.kind = "real";
  ds.mm_per_px = mm_per_px;
  if (track.image_width > 0) {
    ds.width_px = track.image_width;
    ds.height_px = track.image_height;
  }
  ds.principal_px = Vec2((ds.width_px - 1) / 2.0, (ds.height_px - 1) / 2.0);
  ds.markers_rest_px = track.rest_px;
  // tsd/1 readers require every sample to name a listed indenter with a mesh: unknown contacts get a
  // clearly labelled proxy (a 1 mm sphere), never to be used as the real geometry.
  ds.indenters = {{kUnknownContact,
                   {{"mesh", "meshes/unknown_contact.obj"},
                    {"proxy",
                     "contact geometry unknown (fingertip, grasped object or unmodelled indenter); "
                     "this 1 mm sphere only satisfies the format"}}}};
  ds.mesh_files = {{"meshes/unknown_contact.obj", sphere_obj(0.001)}};
  TsdSampleOut s;
  s.id = sample_id;
  s.indenter = kUnknownContact;
  s.dt_s = dt_s;
  s.disp_px = track.disp_px;
  s.X_EI.assign(track.disp_px.size(), Pose::Identity());
  ds.samples.push_back(std::move(s));
  ds.provenance = source_note;
  return ds;
}

ImportReport import_gsrobotics(const std::string& in_dir, const std::string& out_dir, const TrackerOptions& opts,
                               double mm_per_px, bool keep_frames) {
  require_dir(in_dir);
  std::vector<fs::path> videos;
  for (const auto& e : fs::directory_iterator(in_dir))
    if (e.path().extension() == ".avi") videos.push_back(e.path());
  std::sort(videos.begin(), videos.end());
  if (videos.empty()) throw InputError(in_dir, "no .avi recordings");
  ImportReport report;
  for (const auto& v : videos) {
    const std::string stem = v.stem().string();
    const std::string origin = "GelSight Mini recording " + v.filename().string() +
                               " from gelsightinc/gsrobotics (GPL-3.0), see raw/gsrobotics_tracking/SOURCE.md; contact "
                               "is a human fingertip (no indenter geometry, pose or force)." +
                               (stem.rfind("video_", 0) == 0 ? " The video carries the vendor tracker's red arrows; "
                                                               "the tracker masks and fills them before detecting."
                                                             : "");
    import_video(v.string(), (fs::path(out_dir) / stem).string(), "gsrobotics_" + stem, opts, mm_per_px, origin,
                 "GPL-3.0", nlohmann::json::object(), report, keep_frames);
  }
  return report;
}

ImportReport import_incipient_slip(const std::string& in_dir, const std::string& out_dir, const TrackerOptions& opts,
                                   double mm_per_px, bool keep_frames) {
  require_dir(in_dir);
  std::vector<fs::path> experiments;
  for (const auto& e : fs::directory_iterator(in_dir))
    if (e.is_directory()) experiments.push_back(e.path());
  std::sort(experiments.begin(), experiments.end());
  ImportReport report;
  for (const auto& exp : experiments) {
    const bool slip = fs::exists(exp / "slip.txt");
    std::vector<fs::path> clips;
    for (const auto& e : fs::directory_iterator(exp))
      if (e.path().extension() == ".avi") clips.push_back(e.path());
    std::sort(clips.begin(), clips.end());
    for (const auto& clip : clips) {
      const std::string name = exp.filename().string() + "_" + clip.stem().string();
      const std::string origin =
          "Incipient-slip grasp recording " + exp.filename().string() + "/" + clip.filename().string() +
          " from amitparag/Incipient-Slip-Detection (BSD-2-Clause), see raw/incipient_slip/SOURCE.md: a GelSight "
          "Mini fingertip of a Franka gripper grasping, lifting and shaking a household object. Sample field "
          "slip_label: true when the experiment folder holds slip.txt (the authors labelled the run as containing "
          "slip), false otherwise (no slip label).";
      import_video(clip.string(), (fs::path(out_dir) / name).string(), name, opts, mm_per_px, origin, "BSD-2-Clause",
                   nlohmann::json{{"slip_label", slip}}, report, keep_frames);
    }
  }
  if (report.lines.empty()) throw InputError(in_dir, "no experiment folders with .avi clips");
  return report;
}

double sphere_depth_from_contact_radius(double R, double a) {
  if (!(a >= 0) || a > R) return kNaN;
  return R - std::sqrt(R * R - a * a);
}

SphereContactEstimate estimate_sphere_contact_with_radius(const std::vector<Vec2>& rest, const std::vector<Vec2>& disp,
                                                          const Vec2& centre_px, double a_px, double a_sigma_px) {
  SphereContactEstimate e;
  std::vector<double> dx, dy;
  for (const auto& d : disp) dx.push_back(d.x()), dy.push_back(d.y());
  e.drift_px = Vec2(median(dx), median(dy));
  e.centre_px = centre_px;
  e.a_px = a_px;
  e.a_sigma_px = a_sigma_px;
  std::vector<Vec2> inside;
  Vec2 mean = Vec2::Zero();
  for (std::size_t i = 0; i < rest.size(); ++i)
    if ((rest[i] - centre_px).norm() <= a_px) inside.push_back(disp[i] - e.drift_px), mean += inside.back();
  e.markers_inside = static_cast<int>(inside.size());
  if (!inside.empty()) {
    mean /= double(inside.size());
    double var = 0;
    for (const auto& v : inside) var += (v - mean).squaredNorm();
    // Standard error of the mean, with the 1 px integer quantisation of the CSV added in quadrature.
    e.travel_sigma_px = std::sqrt(var / double(inside.size()) / double(inside.size()) + 1.0 / 12.0);
  }
  e.travel_px = mean;
  return e;
}

SphereContactEstimate estimate_sphere_contact(const std::vector<Vec2>& rest, const std::vector<Vec2>& disp,
                                              double pitch) {
  SphereContactEstimate e;
  const std::size_t n = rest.size();
  std::vector<double> dx, dy;
  for (const auto& d : disp) dx.push_back(d.x()), dy.push_back(d.y());
  e.drift_px = Vec2(median(dx), median(dy));
  std::vector<Vec2> d(n);
  double peak = 0;
  for (std::size_t i = 0; i < n; ++i) d[i] = disp[i] - e.drift_px, peak = std::max(peak, d[i].norm());
  // Centre: |d|-weighted centroid of the strongly displaced markers.
  double sw = 0;
  for (std::size_t i = 0; i < n; ++i)
    if (d[i].norm() >= 0.5 * peak) e.centre_px += d[i].norm() * rest[i], sw += d[i].norm();
  if (sw > 0) e.centre_px /= sw;
  // Contact radius: the ring (width half a pitch) with the largest mean radial displacement.
  const double ring = 0.5 * pitch;
  std::vector<double> sum, count;
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2 r = rest[i] - e.centre_px;
    const double rn = r.norm();
    if (rn < 1e-9) continue;
    const std::size_t k = static_cast<std::size_t>(rn / ring);
    if (k >= sum.size()) sum.resize(k + 1, 0.0), count.resize(k + 1, 0.0);
    sum[k] += d[i].dot(r / rn), count[k] += 1;
  }
  double best = -std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < sum.size(); ++k)
    if (count[k] > 0 && sum[k] / count[k] > best) best = sum[k] / count[k], e.a_px = (k + 0.5) * ring;
  e.a_sigma_px = 0.5 * pitch;
  return estimate_sphere_contact_with_radius(rest, disp, e.centre_px, e.a_px, e.a_sigma_px);
}

std::string sphere_obj(double r, int slices, int stacks) {
  std::ostringstream o;
  o << "# UV sphere, radius " << r << " m, centred at the origin, outward normals (counter-clockwise faces)\n";
  o << "v 0 0 " << r << "\n";
  for (int i = 1; i < stacks; ++i) {
    const double th = M_PI * i / stacks;
    for (int j = 0; j < slices; ++j) {
      const double ph = 2 * M_PI * j / slices;
      o << "v " << r * std::sin(th) * std::cos(ph) << " " << r * std::sin(th) * std::sin(ph) << " " << r * std::cos(th)
        << "\n";
    }
  }
  o << "v 0 0 " << -r << "\n";
  auto ring = [&](int i, int j) { return 2 + (i - 1) * slices + (j % slices); };  // 1-based OBJ index
  const int south = 2 + (stacks - 1) * slices;
  for (int j = 0; j < slices; ++j) o << "f 1 " << ring(1, j) << " " << ring(1, j + 1) << "\n";
  for (int i = 1; i < stacks - 1; ++i)
    for (int j = 0; j < slices; ++j) {
      o << "f " << ring(i, j) << " " << ring(i + 1, j) << " " << ring(i + 1, j + 1) << "\n";
      o << "f " << ring(i, j) << " " << ring(i + 1, j + 1) << " " << ring(i, j + 1) << "\n";
    }
  for (int j = 0; j < slices; ++j)
    o << "f " << ring(stacks - 1, j) << " " << south << " " << ring(stacks - 1, j + 1) << "\n";
  return o.str();
}

namespace {
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
       << kAxisNote
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
  require_dir(in_dir);
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

ImportReport import_feats(const std::string& in_dir, const std::string& out_dir) {
  require_dir(in_dir);
  const std::string nocontact_path = (fs::path(in_dir) / "nocontact.png").string();
  const std::string contact_path = (fs::path(in_dir) / "cuboid_10mm_contact.png").string();
  std::vector<cv::Mat> frames;
  for (const auto& p : {nocontact_path, contact_path}) {
    cv::Mat img = cv::imread(p, cv::IMREAD_COLOR);  // drops the contact frame's alpha channel
    if (img.empty()) throw InputError(p, "cannot read image");
    frames.push_back(img);
  }
  if (frames[0].size() != frames[1].size()) throw InputError(contact_path, "size differs from nocontact.png");
  TrackerOptions opts;
  opts.rest_frames = 1;  // the no-contact frame is the rest
  opts.grid_rows = 7;
  opts.grid_cols = 9;
  const TrackResult r = track_frames(frames, opts);
  // point_correspondences.yaml: 10 mm = 140 px.
  constexpr double kMmPerPx = 10.0 / 140.0;
  std::string prov =
      "FEATS sample from feats-ai/feats (MIT), see raw/feats/SOURCE.md: frame 0 = nocontact.png (rest), frame 1 = "
      "cuboid_10mm_contact.png (alpha dropped), a 10 mm cuboid pressed into a GelSight Mini. Markers tracked by "
      "shearbench's tracker (rest = frame 0, expected grid 7 rows x 9 cols): " +
      track_summary(r) + ". The real indenter is a 10 mm cuboid; its pose is unknown. Scale " +
      format_number(kMmPerPx, "%.4f") +
      " mm/px from the authors' point_correspondences.yaml (10 mm = 140 px); "
      "their world axes are rotated 90 degrees against the image, we keep image axes. " +
      kAxisNote + " " + kPoseNote +
      " The gel is domed (4.0 mm at the centre, 2.75 mm at the edge); written as flat 4.0 mm here.";
  for (const auto& w : r.warnings) prov += " Tracker warning: " + w + ".";
  TsdDatasetOut ds = dataset_from_track(r, "feats_cuboid", "cuboid_contact", 1.0, kMmPerPx, prov);
  ds.license = "MIT";
  ds.gel_thickness_m = 0.004;
  ds.samples.front().frames = frames;
  write_tsd_dataset(ds, out_dir);
  ImportReport report;
  report.datasets.push_back(out_dir);
  report.lines.push_back("feats: " + track_summary(r));
  return report;
}

}  // namespace sb

// ---------------------------------------------------------------------------------------------------------------
// ---------------------------------------------------------------------------------------------------------------
// raw/tactip_shear
namespace sb {
namespace {

constexpr double kTactipDtS = 0.02;
constexpr double kDeg = M_PI / 180.0;
const char* kTactipSurface = "flat_surface";

// A closed box of size (sx, sy, sz) metres occupying z in [0, sz] (contact face at z = 0), outward normals.
std::string box_obj(double sx, double sy, double sz) {
  std::ostringstream o;
  o.precision(17);
  for (int k = 0; k < 8; ++k)
    o << "v " << ((k & 1) ? 0.5 : -0.5) * sx << ' ' << ((k & 2) ? 0.5 : -0.5) * sy << ' ' << ((k & 4) ? sz : 0.0)
      << '\n';
  // Faces as quads split in two, counter-clockwise seen from outside (1-based vertex indices).
  const int quads[6][4] = {{1, 3, 4, 2}, {5, 6, 8, 7}, {1, 2, 6, 5}, {3, 7, 8, 4}, {1, 5, 7, 3}, {2, 4, 8, 6}};
  for (const auto& q : quads)
    o << "f " << q[0] << ' ' << q[1] << ' ' << q[2] << "\nf " << q[0] << ' ' << q[2] << ' ' << q[3] << '\n';
  return o.str();
}

struct TactipTarget {
  std::string image;
  int number = 0;
  double depth_mm = 0, rx_deg = 0, ry_deg = 0, sx_mm = 0, sy_mm = 0, twist_deg = 0;
};

// One CSV cell as written by spreadsheets and pandas: surrounding blanks and a pair of double quotes dropped.
std::string csv_cell(std::string c) {
  const auto blank = [](char ch) { return ch == ' ' || ch == '\t' || ch == '\r'; };
  while (!c.empty() && blank(c.back())) c.pop_back();
  std::size_t b = 0;
  while (b < c.size() && blank(c[b])) ++b;
  c.erase(0, b);
  if (c.size() >= 2 && c.front() == '"' && c.back() == '"') c = c.substr(1, c.size() - 2);
  return c;
}

std::vector<std::string> csv_cells(const std::string& line) {
  std::vector<std::string> cells;
  std::stringstream ss(line);
  for (std::string c; std::getline(ss, c, ',');) cells.push_back(csv_cell(c));
  if (!line.empty() && line.back() == ',') cells.emplace_back();
  return cells;
}

// targets.csv as users have it: LF or CRLF line ends, a UTF-8 byte-order mark, the columns in any order with
// others beside them (found by name), the rows in any order.
std::vector<TactipTarget> read_tactip_targets(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, "cannot open");
  std::string line;
  std::getline(in, line);
  if (line.rfind("\xEF\xBB\xBF", 0) == 0) line.erase(0, 3);
  const std::vector<std::string> header = csv_cells(line);
  auto col = [&](const std::string& name) {
    const auto it = std::find(header.begin(), header.end(), name);
    if (it == header.end()) throw InputError(path, 1, 1, "column '" + name + "' missing");
    return static_cast<std::size_t>(it - header.begin());
  };
  const std::size_t ci = col("sensor_image"), cz = col("pose_z"), crx = col("pose_Rx"), cry = col("pose_Ry"),
                    csx = col("shear_x"), csy = col("shear_y"), crz = col("shear_Rz");
  std::vector<TactipTarget> out;
  int lineno = 1;
  while (std::getline(in, line)) {
    ++lineno;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (csv_cell(line).empty()) continue;
    const std::vector<std::string> cells = csv_cells(line);
    if (cells.size() != header.size())
      throw InputError(path, lineno, 1,
                       "expected " + std::to_string(header.size()) + " columns, got " + std::to_string(cells.size()));
    auto num = [&](std::size_t c) {
      char* end = nullptr;
      const double v = std::strtod(cells[c].c_str(), &end);
      if (end == cells[c].c_str() || *end != '\0' || !std::isfinite(v))
        throw InputError(path, lineno, int(c) + 1, "'" + cells[c] + "' is not a finite number");
      return v;
    };
    TactipTarget t;
    t.image = cells[ci];
    if (std::sscanf(t.image.c_str(), "image_%d.png", &t.number) != 1 || t.number <= 0)
      throw InputError(path, lineno, int(ci) + 1, "sensor_image '" + t.image + "' is not image_N.png with N > 0");
    t.depth_mm = num(cz);
    t.rx_deg = num(crx);
    t.ry_deg = num(cry);
    t.sx_mm = num(csx);
    t.sy_mm = num(csy);
    t.twist_deg = num(crz);
    out.push_back(t);
  }
  if (out.empty()) throw InputError(path, "no samples");
  return out;
}

// Motion label: the larger of shear (|s| / 5 mm) and twist (|w| / 5 deg), both normalised by the collection's
// usual range; a sample with both under a quarter of it is a press (+ tilt): "dilation". A label for the
// per-motion scores, not a measurement.
std::string tactip_motion(const TactipTarget& t) {
  const double s = std::hypot(t.sx_mm, t.sy_mm) / 5.0, w = std::abs(t.twist_deg) / 5.0;
  if (std::max(s, w) < 0.25) return "dilation";
  return s >= w ? "shear" : "twist";
}

// A grey image, mirrored left-right when the sensor says its camera sees the tool axes mirrored (so that E,
// whose x/y are the image's u/v, stays right-handed).
cv::Mat read_grey(const std::string& path, bool mirror = false) {
  cv::Mat img = cv::imread(path, cv::IMREAD_GRAYSCALE);
  if (img.empty()) throw InputError(path, "cannot read image");
  if (mirror) cv::flip(img, img, 1);
  return img;
}

// Covariates of a sample's pin field for the prior (pin_field_prior.hpp), inputs scaled to about [-1, 1]
// (the scale only conditions the regression; its predictions do not depend on it): the press d and d^2 (the
// contact grows with the press), the tilt (a, b) to third order (it moves the contact across the dome) alone
// and times d, the slide (sx, sy) and twist w alone and times d and the tilt (the stick region's size, hence
// how much of the slide the skin follows, grows with the press).
Eigen::VectorXd tactip_covariates(const TactipTarget& t) {
  const double d = t.depth_mm / 5.0, a = t.rx_deg / 25.0, b = t.ry_deg / 25.0, sx = t.sx_mm / 5.0, sy = t.sy_mm / 5.0,
               w = t.twist_deg / 5.0;
  std::vector<double> f{1.0, d, d * d};
  for (double x : {a, b, a * a, a * b, b * b, a * a * a, a * a * b, a * b * b, b * b * b}) {
    f.push_back(x);
    f.push_back(d * x);
  }
  for (double x : {sx, sy, w}) {
    f.push_back(x);
    f.push_back(d * x);
    f.push_back(a * x);
    f.push_back(b * x);
  }
  return Eigen::Map<const Eigen::VectorXd>(f.data(), Eigen::Index(f.size()));
}

}  // namespace

int tactip_prior_min_calibration_samples() { return 2 * static_cast<int>(tactip_covariates(TactipTarget{}).size()); }

namespace {

struct TactipSplit {
  std::string name;
  std::vector<TactipTarget> targets;
  std::vector<std::vector<PinDetection>> detections;
};

// The rest image: images/image_0.png of the calibration split when it exists (the undeformed skin); otherwise the
// calibration split's shallowest press, the lightest of those within 2 % of the depth range of it (least slide,
// twist and tilt, each over its range), which is then the rest and no sample.
struct TactipRest {
  std::string path;
  std::string why;
  int number = 0;  // 0: image_0.png
  double depth_mm = kNaN;
};
TactipRest choose_tactip_rest(const fs::path& in, std::vector<TactipTarget>* calibration) {
  TactipRest r;
  r.path = (in / "calibration" / "images" / "image_0.png").string();
  if (fs::exists(r.path)) {
    r.why = "calibration/images/image_0.png, the undeformed reference";
    return r;
  }
  auto& t = *calibration;
  double dmin = kInf, dmax = -kInf, smax = 0, wmax = 0, tmax = 0;
  for (const auto& x : t) {
    dmin = std::min(dmin, x.depth_mm);
    dmax = std::max(dmax, x.depth_mm);
    smax = std::max(smax, std::hypot(x.sx_mm, x.sy_mm));
    wmax = std::max(wmax, std::abs(x.twist_deg));
    tmax = std::max(tmax, std::hypot(x.rx_deg, x.ry_deg));
  }
  auto over = [](double v, double range) { return range > 0 ? v / range : 0.0; };
  std::size_t best = 0;
  double best_load = kInf;
  for (std::size_t k = 0; k < t.size(); ++k) {
    if (t[k].depth_mm > dmin + 0.02 * (dmax - dmin)) continue;
    const double load = over(std::hypot(t[k].sx_mm, t[k].sy_mm), smax) + over(std::abs(t[k].twist_deg), wmax) +
                        over(std::hypot(t[k].rx_deg, t[k].ry_deg), tmax);
    if (load < best_load) {
      best_load = load;
      best = k;
    }
  }
  r.number = t[best].number;
  r.depth_mm = t[best].depth_mm;
  r.path = (in / "calibration" / "images" / t[best].image).string();
  r.why = "calibration/images/" + t[best].image + ", the shallowest press (" + format_number(r.depth_mm, "%.3f") +
          " mm; no images/image_0.png), which is the rest and not a sample";
  t.erase(t.begin() + std::ptrdiff_t(best));
  return r;
}

TactipSplit read_tactip_split(const fs::path& in, const std::string& name, std::vector<TactipTarget> targets,
                              const PinReference& ref, const cv::Mat& ref_img, bool mirror,
                              const TactipImportOptions& options, ImportReport& report) {
  const fs::path sdir = in / name;
  TactipSplit sp;
  sp.name = name;
  sp.targets = std::move(targets);
  const std::string other_ref = (sdir / "images" / "image_0.png").string();
  if (name != "calibration" && fs::exists(other_ref)) {
    const cv::Mat o = read_grey(other_ref, mirror);
    if (o.size() != ref_img.size() || cv::norm(o, ref_img, cv::NORM_INF) != 0)
      report.lines.push_back(name + ": its image_0.png differs from calibration's rest; calibration's is the rest");
  }
  for (const auto& t : sp.targets) {
    const std::string ipath = (sdir / "images" / t.image).string();
    const cv::Mat img = read_grey(ipath, mirror);
    if (img.size() != ref_img.size()) throw InputError(ipath, "image size differs from the reference");
    sp.detections.push_back(detect_pins(img, options.tracker, ref.area_px));
  }
  return sp;
}

// The targets of one split, the first max_samples_per_split rows when set.
std::vector<TactipTarget> read_split_targets(const fs::path& in, const std::string& name,
                                             const TactipImportOptions& options) {
  std::vector<TactipTarget> t = read_tactip_targets((in / name / "targets.csv").string());
  if (options.max_samples_per_split > 0 && t.size() > std::size_t(options.max_samples_per_split))
    t.resize(std::size_t(options.max_samples_per_split));
  return t;
}

// The prior of every sample's pin field, fitted on the calibration split alone by continuation in depth over the
// split's own depth range (by default a first stage over its shallowest quarter, then steps of a sixteenth),
// limits on a 0.05 mm grid.
ContinuationResult fit_tactip_prior(const PinReference& ref, const TactipSplit& cal,
                                    const TactipImportOptions& options) {
  std::vector<Eigen::VectorXd> x;
  std::vector<double> depth;
  for (const auto& t : cal.targets) {
    x.push_back(tactip_covariates(t));
    depth.push_back(t.depth_mm);
  }
  const auto [lo, hi] = std::minmax_element(depth.begin(), depth.end());
  const double range = *hi - *lo;
  auto grid = [](double v) { return std::max(0.05, std::round(v / 0.05) * 0.05); };
  const double first = std::isfinite(options.prior_first_depth_mm) ? options.prior_first_depth_mm
                                                                   : grid(*lo + range / 4.0);
  const double step = std::isfinite(options.prior_step_mm) ? options.prior_step_mm : grid(range / 16.0);
  ContinuationOptions c;
  for (double d = first; d < *hi - 1e-9; d += step) c.limits.push_back(d);
  c.limits.push_back(std::numeric_limits<double>::infinity());
  return fit_prior_by_continuation(ref, cal.detections, x, depth, options.tracker, c);
}

void report_prior(const ContinuationResult& fit, std::size_t calibration_samples, ImportReport& report) {
  if (fit.prior.empty())
    report.lines.push_back("prior: too few calibration samples (" + std::to_string(calibration_samples) +
                           ") for the per-pin regression; every image tracked without a prior (deep presses "
                           "lose pins rather than guess)");
  for (const auto& st : fit.stages)
    report.lines.push_back(
        std::string(st.refine ? "prior refinement pass" : "prior stage") + ", depth " +
        (std::isinf(st.limit) ? std::string("all") : "<= " + format_number(st.limit, "%.2f") + " mm") + ": " +
        std::to_string(st.accepted) + " of " + std::to_string(st.candidates) +
        " calibration samples accepted; |tracked - prior| median " + format_number(st.miss_median_px, "%.2f") +
        " px, p95 " + format_number(st.miss_p95_px, "%.2f") + " px");
}

// One image's pins: tracked against the prior, then checked; the pins the check doubts are lost, not
// kept (a kept pin must be the right pin), unless options.lattice_check is off.
struct CheckedPins {
  std::vector<Vec2> disp;
  LatticeCheckResult check;
  int suspect = 0;  // tracked pins the check doubts
  int kept() const {
    int n = 0;
    for (const auto& d : disp) n += d.allFinite();
    return n;
  }
};

CheckedPins track_checked(const PinReference& ref, const std::vector<PinDetection>& detections,
                          const std::vector<Vec2>& prior, const TactipImportOptions& options) {
  CheckedPins out;
  out.disp = track_pins(ref, detections, options.tracker, prior);
  out.check = check_lattice(ref, out.disp, detections, LatticeCheckOptions{}, prior);
  for (std::size_t i = 0; i < out.disp.size(); ++i) out.suspect += out.check.suspect[i] && out.disp[i].allFinite();
  if (options.lattice_check) out.disp = without_suspects(out.disp, out.check);
  return out;
}

nlohmann::json lattice_check_json(const CheckedPins& p, std::size_t detections, bool dropped) {
  const LatticeCheckResult& c = p.check;
  return {{"slipped_pairs", c.slipped_pairs},
          {"flipped_triangles", c.flipped_triangles},
          {"skipped_sites", c.skipped_sites},
          {"prior_misses", c.prior_misses},
          {"median_prior_miss_px", c.median_prior_miss_px},
          {"coherent_prior_miss_px", c.coherent_prior_miss_px},
          {"registration_margin", c.registration_margin},
          {"field_shifted", c.field_shifted},
          {"worst_relative_step", c.worst_relative_step},
          {"detached_pins", c.detached_pins},
          {"pins_dropped", dropped ? p.suspect : 0},
          {"pins_suspect", p.suspect},
          {"detections", detections}};
}

}  // namespace

// Frames (SOURCE.md, env_params.json): the work frame W has z down into the surface (the surface plane is
// z_W = 0, its body z_W > 0), the tool frame S sits at the TacTip's tip with z along the sensor's axis
// (out of the skin). tactip_pose_path returns X_SI with X_SI = X_WS^-1 (S at the undeformed skin apex, +z out
// of the skin); the importer turns S about z into E so that E's x/y are the image's u/v. And
// the indenter frame I = W (contact face z_I = 0, body z_I > 0). The robot sets X_WS: translation
// (shear_x, shear_y, -above) above, (shear_x, shear_y, depth) pressed, (0, 0, depth) final, rotation
// Rz(twist) Ry(ry) Rx(rx) (static x-y-z Euler angles) with the twist going to zero during the slide.
// The path is X_SI = X_WS^-1.
std::vector<Pose> tactip_pose_path(double depth_m, double rx, double ry, double sx_m, double sy_m, double twist,
                                   int slide_steps, double above_m) {
  auto X_WS = [&](double f, double z) {  // f = 1 at the start of the slide, 0 at its end
    Pose X = Pose::Identity();
    X.linear() = (Eigen::AngleAxisd(f * twist, Vec3::UnitZ()) * Eigen::AngleAxisd(ry, Vec3::UnitY()) *
                  Eigen::AngleAxisd(rx, Vec3::UnitX()))
                     .toRotationMatrix();
    X.translation() = Vec3(f * sx_m, f * sy_m, z);
    return X;
  };
  std::vector<Pose> path{X_WS(1.0, -above_m).inverse()};
  const int n = std::max(1, slide_steps);
  for (int k = 0; k <= n; ++k) path.push_back(X_WS(1.0 - double(k) / n, depth_m).inverse());
  return path;
}

namespace {

// The pinhole camera the ring fit starts from: with the ring pitch theta fixed (the skin's pattern), ring 1's
// image radius rho_1 = f sin theta / (a + cos theta), a = (D - R) / r_p, started at a = 2 (the camera a dome's
// diameter below the apex; the fit moves it); with the focal length given, the distance such that the pin
// sphere's equator is seen at the image's half-width.
Camera tactip_start_camera(int width_px, int height_px, const TactipSensor& s, double ring1_px) {
  Camera c;
  c.model = CameraModel::Pinhole;
  c.width_px = width_px;
  c.height_px = height_px;
  c.principal_px = Vec2((width_px - 1) / 2.0, (height_px - 1) / 2.0);
  c.k1 = s.k1.value;
  const double R = s.dome_radius_mm.value * 1e-3, rp = R - s.pin_depth_mm.value * 1e-3;
  const double theta = s.ring_pitch_deg.value * kDeg;
  if (s.focal_px.source == SensorValueSource::kGiven) {
    c.focal_px = s.focal_px.value;
    c.distance_m = R + c.focal_px * rp / (0.5 * width_px);
  } else {
    constexpr double kStartA = 2.0;
    c.focal_px = ring1_px * (kStartA + std::cos(theta)) / std::sin(theta);
    c.distance_m = R + kStartA * rp;
  }
  if (s.distance_mm.source == SensorValueSource::kGiven) c.distance_m = s.distance_mm.value * 1e-3;
  return c;
}

// The camera from the reference's pins (tactip_geometry_fit.hpp). The rings give the principal point, phi0 and
// one function of the ring index whose slope fixes f theta / (a + 1) and whose curvature fixes a: so with the
// skin's ring pitch (the pattern) fixed they give f and D; with f given, theta. R, the pin depth and k1 are what
// the sensor says (they trade with D and with a). The sensor's camera values are set from the fit.
TactipGeometryFit fit_tactip_camera(const std::vector<Vec2>& rest_px, int width_px, int height_px, TactipSensor* s,
                                    const std::string& where) {
  const TactipRings rings = assign_tactip_rings(rest_px, where);
  TactipGeometryFitOptions o;
  o.dome_radius_m = s->dome_radius_mm.value * 1e-3;
  o.pin_depth_m = s->pin_depth_mm.value * 1e-3;
  o.initial = tactip_start_camera(width_px, height_px, *s, rings.ring_radius_px.at(1));
  const bool focal_given = s->focal_px.source == SensorValueSource::kGiven;
  const bool pitch_given = s->ring_pitch_deg.source == SensorValueSource::kGiven;
  o.fit_focal = !focal_given;
  o.fit_ring_pitch = focal_given && !pitch_given;
  o.ring_pitch_rad = s->ring_pitch_deg.value * kDeg;
  o.fit_distance = s->distance_mm.source != SensorValueSource::kGiven;
  o.fit_k1 = false;
  TactipGeometryFit g = fit_tactip_geometry(rest_px, o, where);
  const std::string how = "fitted to the reference's " + std::to_string(g.pins_used) + " pins in " +
                          std::to_string(g.rings.ring_radius_px.size() - 1) + " rings (RMS " +
                          format_number(g.rms_px, "%.3f") + " px)";
  auto set = [&](SensorValue& v, double value, double sigma, bool fitted) {
    if (!fitted) return;
    v = {value, sigma, SensorValueSource::kIdentified, how};
  };
  set(s->focal_px, g.camera.focal_px, g.sigma_focal_px, o.fit_focal);
  set(s->distance_mm, g.camera.distance_m * 1e3, g.sigma_distance_m * 1e3, o.fit_distance);
  set(s->ring_pitch_deg, g.ring_pitch_rad / kDeg, g.sigma_pitch_rad / kDeg, o.fit_ring_pitch);
  if (s->principal_u_px.source != SensorValueSource::kGiven)
    set(s->principal_u_px, g.camera.principal_px.x(), g.sigma_principal_px.x(), true);
  if (s->principal_v_px.source != SensorValueSource::kGiven)
    set(s->principal_v_px, g.camera.principal_px.y(), g.sigma_principal_px.y(), true);
  else
    g.camera.principal_px = Vec2(s->principal_u_px.value, s->principal_v_px.value);
  return g;
}

nlohmann::json geometry_fit_json(const TactipGeometryFit& g, const TactipGeometryFitOptions& o) {
  constexpr double kRadToDeg = 180.0 / M_PI;
  std::vector<std::string> fitted{"principal_px", "azimuth_deg"}, fixed{"k1", "gel.radius_m", "markers_depth_m"};
  (o.fit_distance ? fitted : fixed).push_back("distance_m");
  (o.fit_focal ? fitted : fixed).push_back("focal_px");
  (o.fit_ring_pitch ? fitted : fixed).push_back("ring_pitch_deg");
  return {{"fitted", fitted},
          {"fixed", fixed},
          {"pattern", "apex pin + rings i = 1.. of 6 i pins at polar angle i * ring_pitch on the pin sphere"},
          {"rings", int(g.rings.ring_radius_px.size()) - 1},
          {"pins_used", g.pins_used},
          {"rms_px", g.rms_px},
          {"max_px", g.max_px},
          {"ring_pitch_deg", g.ring_pitch_rad * kRadToDeg},
          {"outer_ring_polar_deg", g.outer_ring_polar_rad() * kRadToDeg},
          {"azimuth_deg", g.azimuth_rad * kRadToDeg},
          {"sigma_principal_px", {g.sigma_principal_px.x(), g.sigma_principal_px.y()}},
          {"sigma_focal_px", g.sigma_focal_px},
          {"sigma_distance_m", g.sigma_distance_m},
          {"sigma_ring_pitch_deg", g.sigma_pitch_rad * kRadToDeg}};
}

std::string geometry_fit_line(const TactipGeometryFit& g, const TactipSensor& s) {
  const Camera& c = g.camera;
  auto pm = [](double v, double sigma, const char* fmt) {
    return format_number(v, fmt) + (std::isfinite(sigma) ? " +- " + format_number(sigma, "%.2g") : std::string());
  };
  return "geometry fit on the reference's pin rings: " + std::to_string(g.pins_used) + " pins in " +
         std::to_string(g.rings.ring_radius_px.size() - 1) + " rings, principal point (" +
         format_number(c.principal_px.x(), "%.2f") + ", " + format_number(c.principal_px.y(), "%.2f") + ") +- " +
         format_number(g.sigma_principal_px.x(), "%.2f") + " px, focal " + pm(c.focal_px, g.sigma_focal_px, "%.1f") +
         " px (" + to_string(s.focal_px.source) + "), distance " +
         pm(c.distance_m * 1e3, g.sigma_distance_m * 1e3, "%.2f") + " mm, ring pitch " +
         pm(g.ring_pitch_rad / kDeg, g.sigma_pitch_rad / kDeg, "%.3f") + " deg (" + to_string(s.ring_pitch_deg.source) +
         "; outer ring at " + format_number(g.outer_ring_polar_rad() / kDeg, "%.1f") + " deg); k1 " +
         format_number(c.k1, "%.0f") + ", R " + format_number(s.dome_radius_mm.value, "%.4g") + " mm, pin depth " +
         format_number(s.pin_depth_mm.value, "%.4g") + " mm (" + to_string(s.dome_radius_mm.source) +
         "); residual RMS " + format_number(g.rms_px, "%.3f") + " px, max " + format_number(g.max_px, "%.2f") + " px";
}

// The gel the sensor description gives: the hemispherical dome (footprint = radius) on a 1 mm base.
GelSpec tactip_gel(const TactipSensor& s) {
  GelSpec gel;
  const double R = s.dome_radius_mm.value * 1e-3;
  gel.surface = "spherical_cap";
  gel.radius_m = R;
  gel.footprint_radius_m = R;
  gel.size_m = Vec2(2 * R, 2 * R);
  gel.thickness_m = R + 0.001;
  gel.markers_depth_m = s.pin_depth_mm.value * 1e-3;
  return gel;
}

// Which rest pins the sensor can place: each one's ray must meet the pin sphere on the dome (a pin seen past its
// equator sits on the skin's wall, which the spherical-cap gel does not model). Such pins are left out of the
// dataset (counted in the report), so that every evaluation and fit builds the sensor.
std::vector<char> pins_on_dome(const std::vector<Vec2>& rest_px, const Camera& camera, const GelSpec& gel) {
  std::vector<char> keep(rest_px.size(), 1);
  for (std::size_t i = 0; i < rest_px.size(); ++i) {
    try {
      (void)make_sensor(camera, gel, {rest_px[i]});
    } catch (const InputError&) {
      keep[i] = 0;
    }
  }
  return keep;
}

template <typename T>
std::vector<T> kept_only(const std::vector<T>& v, const std::vector<char>& keep) {
  std::vector<T> out;
  for (std::size_t i = 0; i < v.size(); ++i)
    if (keep[i]) out.push_back(v[i]);
  return out;
}

// Every tracked sample's response to its slide (tactip_sensor.hpp), calibration split only.
std::vector<ShearResponse> shear_responses(const TactipSplit& sp, const std::vector<CheckedPins>& pins) {
  std::vector<ShearResponse> out;
  for (std::size_t k = 0; k < sp.targets.size(); ++k) {
    ShearResponse r;
    const TactipTarget& t = sp.targets[k];
    r.depth_mm = t.depth_mm;
    r.shear_mm = Vec2(t.sx_mm, t.sy_mm);
    int tracked = 0;
    r.response_px = most_displaced_mean(pins[k].disp, &tracked);
    r.tracked = tracked > 0;
    out.push_back(r);
  }
  return out;
}

// The rotation (and handedness) from the calibration split's shallow presses, unless the sensor gives it.
void identify_rotation(const std::vector<ShearResponse>& responses, TactipSensor* s, ImageFromTool* fit,
                       const std::string& where, ImportReport& report, double min_depth_mm = -kInf) {
  if (s->image_from_tool_deg.source == SensorValueSource::kGiven) return;
  try {
    *fit = identify_image_from_tool(responses, where, min_depth_mm);
  } catch (const InputError& e) {
    // Too few slides to tell (a small import): said so, and the tool axes taken as the image's.
    s->image_from_tool_deg = {0.0, kNaN, SensorValueSource::kDefault,
                              std::string("the data cannot tell it: ") + e.what() + "; 0 deg taken"};
    report.lines.push_back("WARNING: image-from-tool rotation: " + s->image_from_tool_deg.how);
    return;
  }
  s->image_from_tool_deg = {
      fit->angle_rad / kDeg, fit->sigma_rad / kDeg, SensorValueSource::kIdentified,
      "fitted to " + std::to_string(fit->samples) + " shallow presses' slide: the most displaced pins move " +
          format_number(fit->gain_px_per_mm, "%.2f") + " px per mm along it, residual " +
          format_number(fit->rms_px, "%.2f") + " px rms of " + format_number(fit->response_rms_px, "%.2f")};
  if (s->mirrored.source != SensorValueSource::kGiven)
    s->mirrored = {double(fit->mirrored), kNaN, SensorValueSource::kIdentified,
                   "the " + std::string(fit->mirrored ? "mirrored" : "rotated") + " fit explains the slide (" +
                       format_number(std::min(fit->rms_px, fit->mirrored_rms_px), "%.2f") + " px rms) and the " +
                       std::string(fit->mirrored ? "rotated" : "mirrored") + " one does not (" +
                       format_number(std::max(fit->rms_px, fit->mirrored_rms_px), "%.2f") + " px)"};
  report.lines.push_back("image-from-tool rotation " + format_number(s->image_from_tool_deg.value, "%.2f") + " +- " +
                         format_number(s->image_from_tool_deg.sigma, "%.2f") + " deg, " +
                         (fit->mirrored ? "mirrored" : "not mirrored") + ": " + s->image_from_tool_deg.how +
                         "; mirrored fit " + format_number(fit->mirrored_rms_px, "%.2f") + " px");
}

// The contact onset from the depth at which the pins begin to follow the slide, unless the sensor gives it.
void identify_onset(std::vector<ShearResponse>& responses, const std::vector<CheckedPins>& pins, double gain_px_per_mm,
                    TactipSensor* s, ImportReport& report) {
  if (s->contact_onset_mm.source == SensorValueSource::kGiven) return;
  for (std::size_t k = 0; k < responses.size(); ++k)
    responses[k].moving_fraction = fraction_moved(pins[k].disp, 0.5 * gain_px_per_mm * responses[k].shear_mm.norm());
  const ContactOnset on = identify_contact_onset(responses);
  s->onset_extrapolated_mm = on.extrapolated_mm;
  s->onset_extrapolated_sigma_mm = on.sigma_mm;
  std::string what = "the fraction of pins following the slide, a line in depth on the " +
                     std::to_string(on.in_contact) + " shallowest pressed samples, meets zero at " +
                     format_number(on.extrapolated_mm, "%.3f") + " +- " + format_number(on.sigma_mm, "%.2g") + " mm";
  if (on.identified) {
    s->contact_onset_mm = {on.extrapolated_mm, on.sigma_mm, SensorValueSource::kIdentified,
                           what + "; " + std::to_string(on.out_of_contact) + " presses (to " +
                               format_number(on.deepest_out_mm, "%.3f") +
                               " mm) move no pin: the poses' depth is counted from it"};
  } else {
    s->contact_onset_mm.how =
        "every press touches (none moves no pin), so the data cannot tell the tool's zero: "
        "the collection's zero depth is taken as the touch (" +
        what + ")";
  }
  report.lines.push_back("contact onset " + format_number(s->contact_onset_mm.value, "%.3f") + " mm (" +
                         to_string(s->contact_onset_mm.source) + "): " + s->contact_onset_mm.how);
}

// The "above" frame's clearance: the dome, turned about its apex by the largest tilt, reaches R (1 - cos tilt)
// past the apex; a quarter of the radius more keeps it clear.
double tactip_above_m(const std::vector<TactipSplit>& splits, double R, double onset_m) {
  double tilt = 0;
  for (const auto& sp : splits)
    for (const auto& t : sp.targets) tilt = std::max(tilt, std::hypot(t.rx_deg, t.ry_deg) * kDeg);
  return R * (1.0 - std::cos(std::min(tilt, M_PI / 2))) + 0.25 * R + std::max(0.0, onset_m);
}

// The tsd/1 sample of one TacTip image: the pose path of the collection procedure (in E), the markers
// (frame 0 the reference, the last frame `disp`, NaN between: not imaged) and, with `ref_img` given, the
// reference and the image as frames 0 and last.
struct TactipSampleFrame {
  double image_from_tool_rad = 0, onset_m = 0, above_m = 0;
  bool mirror = false;
};
TsdSampleOut tactip_sample(const std::string& split, const TactipTarget& t, const std::vector<Vec2>& disp,
                           const TactipImportOptions& options, const TactipSampleFrame& frame, const cv::Mat& ref_img,
                           const fs::path& in) {
  TsdSampleOut s;
  s.id = std::string(split == "calibration" ? "cal_" : "val_") + format_number(t.number, "%04.0f");
  s.motion = tactip_motion(t);
  s.indenter = kTactipSurface;
  s.split = split;
  s.dt_s = kTactipDtS;
  s.pose_known = true;
  s.X_EI = tactip_pose_path(t.depth_mm * 1e-3 - frame.onset_m, t.rx_deg * kDeg, t.ry_deg * kDeg, t.sx_mm * 1e-3,
                            t.sy_mm * 1e-3, t.twist_deg * kDeg, options.slide_steps, frame.above_m);
  Pose X_ES = Pose::Identity();
  X_ES.linear() = Eigen::AngleAxisd(frame.image_from_tool_rad, Vec3::UnitZ()).toRotationMatrix();
  for (auto& X : s.X_EI) X = X_ES * X;
  const std::vector<Vec2> lost(disp.size(), Vec2(kNaN, kNaN));
  s.disp_px.assign(s.X_EI.size(), lost);
  s.disp_px.front() = std::vector<Vec2>(disp.size(), Vec2::Zero());
  s.disp_px.back() = disp;
  if (!ref_img.empty()) {
    s.frames.assign(s.X_EI.size(), cv::Mat());
    s.frames.front() = ref_img;
    s.frames.back() = read_grey((in / split / "images" / t.image).string(), frame.mirror);
  }
  return s;
}

// The dataset's sensor and indenter blocks: the dome, its pins and the camera fitted to the reference's rings.
TsdDatasetOut tactip_dataset(const PinReference& ref, const std::vector<char>& keep, const cv::Mat& ref_img,
                             const TactipGeometryFit& geometry, const TactipGeometryFitOptions& fit_options,
                             const TactipSensor& sensor) {
  TsdDatasetOut ds;
  ds.name = "tactip_shear";
  ds.kind = "real";
  ds.license = "as the source folder states (see its SOURCE.md or licence file)";
  ds.sensor_model = "TacTip midi";
  ds.width_px = ref_img.cols;
  ds.height_px = ref_img.rows;
  ds.camera = geometry.camera;
  ds.principal_px = geometry.camera.principal_px;
  const GelSpec gel = tactip_gel(sensor);
  ds.gel_surface = gel.surface;
  ds.gel_radius_m = gel.radius_m;
  ds.gel_footprint_radius_m = gel.footprint_radius_m;
  ds.gel_size_m = gel.size_m;
  ds.gel_thickness_m = gel.thickness_m;  // the hemisphere on a 1 mm base (a solid for the SDF)
  ds.markers_depth_m = gel.markers_depth_m;
  ds.markers_rest_px = kept_only(ref.rest_px, keep);
  ds.sensor_extra["tactip"] = {
      {"skin", "hemispherical dome, pins on its inner surface below the contact surface (gel: spherical_cap)"},
      {"camera",
       "pinhole from inside along +z_E; fitted to the reference's pin rings with the skin's values "
       "(sensor.tactip.description says which were identified, given or defaulted; docs/sensors.md)"},
      {"pin_pitch_px", ref.pitch_px},
      {"pin_area_px", ref.area_px},
      {"geometry_fit", geometry_fit_json(geometry, fit_options)},
      {"description", to_json(sensor)}};
  ds.indenters = {
      {kTactipSurface,
       {{"mesh", "meshes/flat_surface.obj"},
        {"note", "the 'square' stimulus: a flat surface, face z_I = 0, body z_I > 0 (80 x 80 x 10 mm box)"}}}};
  ds.mesh_files = {{"meshes/flat_surface.obj", box_obj(0.08, 0.08, 0.01)}};
  return ds;
}

// One split's samples (tracked against the reference and the prior) into `ds`, with a summary line in `report`.
// A sample with no pin tracked is left out (counted, with the reason): nothing of it could be scored.
void add_tactip_split(const TactipSplit& sp, const std::vector<CheckedPins>& pins, const std::vector<char>& keep,
                      const TactipSampleFrame& frame, const cv::Mat& ref_img, const fs::path& in,
                      const TactipImportOptions& options, bool prior_empty, TsdDatasetOut& ds, ImportReport& report,
                      std::string* notes) {
  std::vector<double> kept;
  int worst_number = -1, slipped_samples = 0, empty_samples = 0;
  double worst = 2.0;
  const std::size_t pin_count = ds.markers_rest_px.size();
  for (std::size_t k = 0; k < sp.targets.size(); ++k) {
    const TactipTarget& t = sp.targets[k];
    const std::vector<Vec2> disp = kept_only(pins[k].disp, keep);
    int found = 0;
    for (const Vec2& d : disp) found += d.allFinite();
    slipped_samples += !pins[k].check.clean();
    const double frac = double(found) / double(pin_count);
    kept.push_back(frac);
    if (frac < worst) {
      worst = frac;
      worst_number = t.number;
    }
    if (found == 0) {
      ++empty_samples;
      continue;
    }
    TsdSampleOut s = tactip_sample(sp.name, t, disp, options, frame, options.frames ? ref_img : cv::Mat(), in);
    s.extra = {{"image", sp.name + "/images/" + t.image},
               {"pins_tracked", found},
               {"lattice_check", lattice_check_json(pins[k], sp.detections[k].size(), options.lattice_check)},
               {"targets",
                {{"depth_mm", t.depth_mm},
                 {"tilt_deg", {t.rx_deg, t.ry_deg}},
                 {"shear_mm", {t.sx_mm, t.sy_mm}},
                 {"twist_deg", t.twist_deg}}}};
    ds.samples.push_back(std::move(s));
  }
  std::sort(kept.begin(), kept.end());
  const auto below = std::count_if(kept.begin(), kept.end(), [](double f) { return f < 0.95; });
  report.lines.push_back(sp.name + ": " + std::to_string(kept.size()) + " images, " + std::to_string(pin_count) +
                         " pins; kept fraction min " + format_number(kept.front(), "%.4f") + " (image_" +
                         std::to_string(worst_number) + "), p5 " + format_number(kept[kept.size() / 20], "%.4f") +
                         ", median " + format_number(kept[kept.size() / 2], "%.4f") +
                         "; images under 0.95: " + std::to_string(below) +
                         "; images not clean under the lattice check: " + std::to_string(slipped_samples));
  if (empty_samples > 0) {
    report.lines.push_back("WARNING: " + sp.name + ": " + std::to_string(empty_samples) + " of " +
                           std::to_string(kept.size()) + " samples have no pin tracked (0 of " +
                           std::to_string(pin_count) + "): left out of the dataset, so of every fit and score" +
                           (prior_empty && options.use_prior
                                ? ": the pin prior needs " + std::to_string(tactip_prior_min_calibration_samples()) +
                                      " calibration samples (--max-samples " +
                                      std::to_string(tactip_prior_min_calibration_samples()) + " or more, or 0 for all)"
                                : std::string()));
    *notes += " " + sp.name + ": " + std::to_string(empty_samples) + " of " + std::to_string(kept.size()) +
              " images left out, no pin tracked in them.";
  }
}

// What the dataset is and how it was made (the tsd/1 provenance text).
std::string tactip_provenance(const fs::path& in, const PinReference& ref, const TactipRest& rest,
                              const TactipImportOptions& options, const TactipSensor& s) {
  std::string source = "TacTip shear data from " + in.filename().string() + "/";
  if (fs::exists(in / "SOURCE.md")) source += " (its SOURCE.md says where it comes from)";
  return source +
         ": a flat surface pressed at a tilt, slid and twisted in contact, one thresholded image per sample. Rest = " +
         rest.why + ", " + std::to_string(ref.rest_px.size()) + " pins, pitch " + format_number(ref.pitch_px, "%.2f") +
         " px. Pins tracked by shearbench's pin tracker (blob detection, global "
         "affine then local nearest-neighbour correspondence, lost pins NaN)" +
         std::string(options.use_prior ? " against a prior field predicted from each sample's targets by a per-pin "
                                         "regression fitted on the calibration split alone (continuation from "
                                         "shallow to deep presses)"
                                       : "") +
         std::string(options.lattice_check ? "; pins the lattice-slip check doubts (a skipped lattice site, a "
                                             "crossing, a jump between neighbours, a detached island, a whole-field "
                                             "shift) are lost: see 'lattice_check' per sample"
                                           : "") +
         ". poses.csv is the collection procedure: frame 0 above (clear of the surface), frame 1 pressed at (pose + "
         "shear), frames 2.." +
         std::to_string(options.slide_steps + 1) +
         " the slide to the final pose (shear and twist going linearly to zero), the press depth counted from the "
         "contact onset (" +
         format_number(s.contact_onset_mm.value, "%.3f") + " mm, " + to_string(s.contact_onset_mm.source) +
         "); markers.csv: frame 0 zero (the reference), NaN while not imaged, the tracked pins at the last frame. "
         "Frames: S = the tool frame at the skin apex (+z out of the skin), I = the work frame on the surface (z "
         "into it); rotation Rz(twist) Ry(pose_Ry) Rx(pose_Rx) static Euler as the robot library's sxyz; E = Rz(" +
         format_number(s.image_from_tool_deg.value, "%.2f") + " deg) S so that E's x/y are the image's u/v (" +
         to_string(s.image_from_tool_deg.source) + (s.mirrored.value != 0 ? "; images mirrored left-right" : "") +
         "). Sensor: sensor.tactip.description (every value with its source and uncertainty; docs/sensors.md). "
         "Motion label: shear or twist by the larger normalised magnitude (|shear| / 5 mm vs |twist| / 5 deg), "
         "dilation (press + tilt) when both are under 0.25. Targets per sample under 'targets' (mm, deg).";
}

}  // namespace

namespace {

// The import with the sensor's given values in `sensor`; `mirror_known`: whether its handedness is settled (given,
// or identified by a first pass), so that a mirrored camera is imported again with the images mirrored.
ImportReport import_tactip(const fs::path& in, const std::string& out_dir, const TactipImportOptions& options,
                           TactipSensor sensor, bool mirror_known) {
  const bool mirror = sensor.mirrored.value != 0;
  ImportReport report;
  std::vector<TactipTarget> cal_targets = read_split_targets(in, "calibration", options);
  const TactipRest rest = choose_tactip_rest(in, &cal_targets);
  const cv::Mat ref_img = read_grey(rest.path, mirror);
  const PinReference ref = make_pin_reference(ref_img, options.tracker, rest.path);
  sensor.width_px = ref_img.cols;
  sensor.height_px = ref_img.rows;
  sensor.reference = rest.why;
  report.lines.push_back("reference: " + rest.why);

  const TactipGeometryFit geometry = fit_tactip_camera(ref.rest_px, ref_img.cols, ref_img.rows, &sensor, rest.path);
  TactipGeometryFitOptions fit_options;
  fit_options.fit_focal = sensor.focal_px.source == SensorValueSource::kIdentified;
  fit_options.fit_distance = sensor.distance_mm.source == SensorValueSource::kIdentified;
  fit_options.fit_ring_pitch = sensor.ring_pitch_deg.source == SensorValueSource::kIdentified;
  report.lines.push_back(geometry_fit_line(geometry, sensor));
  const std::vector<char> keep = pins_on_dome(ref.rest_px, geometry.camera, tactip_gel(sensor));
  const auto off_dome = std::count(keep.begin(), keep.end(), 0);
  if (off_dome > 0)
    report.lines.push_back(std::to_string(off_dome) + " of " + std::to_string(keep.size()) +
                           " pins are seen past the dome's equator (on the skin's wall): left out of the markers");

  std::vector<TactipSplit> splits;
  splits.push_back(read_tactip_split(in, "calibration", std::move(cal_targets), ref, ref_img, mirror, options, report));
  splits.push_back(read_tactip_split(in, "validation", read_split_targets(in, "validation", options), ref, ref_img,
                                     mirror, options, report));
  PinFieldPrior prior;
  if (options.use_prior) {
    const ContinuationResult fit = fit_tactip_prior(ref, splits.front(), options);
    prior = fit.prior;
    report_prior(fit, splits.front().targets.size(), report);
  }
  std::vector<std::vector<CheckedPins>> pins(splits.size());
  for (std::size_t s = 0; s < splits.size(); ++s)
    for (std::size_t k = 0; k < splits[s].targets.size(); ++k)
      pins[s].push_back(
          track_checked(ref, splits[s].detections[k], prior.predict(tactip_covariates(splits[s].targets[k])), options));

  std::vector<ShearResponse> responses = shear_responses(splits.front(), pins.front());
  ImageFromTool rotation;
  identify_rotation(responses, &sensor, &rotation, (in / "calibration" / "targets.csv").string(), report);
  if (!mirror_known && sensor.mirrored.value != 0) {
    // The camera sees the tool axes mirrored: again with every image mirrored, so that E stays right-handed.
    report.lines.push_back("the camera sees the tool axes mirrored: importing again with the images mirrored");
    TactipSensor again = tactip_standard_defaults();
    if (!options.sensor_file.empty()) read_tactip_sensor_file(options.sensor_file, &again);
    again.mirrored = sensor.mirrored;
    ImportReport r = import_tactip(in, out_dir, options, again, true);
    report.lines.insert(report.lines.end(), r.lines.begin(), r.lines.end());
    report.datasets = r.datasets;
    return report;
  }
  if (std::isfinite(rotation.gain_px_per_mm))
    identify_onset(responses, pins.front(), rotation.gain_px_per_mm, &sensor, report);
  if (sensor.contact_onset_mm.source == SensorValueSource::kIdentified &&
      sensor.image_from_tool_deg.source == SensorValueSource::kIdentified) {
    // The presses short of the touch moved nothing: the rotation again from those that touch.
    report.lines.push_back("the rotation again from the presses past the contact onset:");
    identify_rotation(responses, &sensor, &rotation, (in / "calibration" / "targets.csv").string(), report,
                      sensor.contact_onset_mm.value);
  }

  if (rest.number != 0) {
    // A press as the rest: undeformed only if it is short of the touch; otherwise its own field is in every
    // displacement (said so: the data hold no better rest).
    const bool clear = sensor.contact_onset_mm.source != SensorValueSource::kDefault &&
                       rest.depth_mm < sensor.contact_onset_mm.value;
    sensor.reference += clear ? "; short of the contact onset, so undeformed"
                              : "; not known to be short of the touch: if it is pressed, its own field is in every "
                                "displacement";
    if (!clear) report.lines.push_back("WARNING: the reference " + rest.why + " may itself be pressed");
  }
  TactipSampleFrame frame;
  frame.image_from_tool_rad = sensor.image_from_tool_deg.value * kDeg;
  frame.onset_m = sensor.contact_onset_mm.value * 1e-3;
  frame.above_m = tactip_above_m(splits, sensor.dome_radius_mm.value * 1e-3, frame.onset_m);
  frame.mirror = mirror;
  TsdDatasetOut ds = tactip_dataset(ref, keep, ref_img, geometry, fit_options, sensor);
  std::string notes;
  for (std::size_t s = 0; s < splits.size(); ++s)
    add_tactip_split(splits[s], pins[s], keep, frame, ref_img, in, options, prior.empty(), ds, report, &notes);
  ds.provenance = tactip_provenance(in, ref, rest, options, sensor) + notes;
  write_tsd_dataset(ds, out_dir);
  report.datasets.push_back(out_dir);
  return report;
}

}  // namespace

ImportReport import_tactip_shear(const std::string& in_dir, const std::string& out_dir,
                                 const TactipImportOptions& options) {
  require_dir(in_dir);
  TactipSensor sensor = tactip_standard_defaults();
  if (!options.sensor_file.empty()) read_tactip_sensor_file(options.sensor_file, &sensor);
  return import_tactip(fs::path(in_dir), out_dir, options, sensor, sensor.mirrored.source == SensorValueSource::kGiven);
}

}  // namespace sb
