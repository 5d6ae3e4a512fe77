// The TacTip shear set importer (import_tactip.hpp).
#include "core/data/import_tactip.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <opencv2/core.hpp>

#include "core/base/error.hpp"
#include "core/base/format.hpp"
#include "core/data/obj_writers.hpp"
#include "core/data/tactip_pins.hpp"
#include "core/data/tactip_sensor.hpp"
#include "core/data/tactip_targets.hpp"
#include "core/sensor/sensor.hpp"
#include "core/sensor/tactip_identify.hpp"
#include "core/sensor/tactip_sensor_camera.hpp"

namespace fs = std::filesystem;

namespace sb {

namespace {

constexpr double kTactipDtS = 0.02;
constexpr double kDeg = M_PI / 180.0;
const char* kTactipSurface = "flat_surface";

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

template <typename T>
std::vector<T> kept_only(const std::vector<T>& v, const std::vector<char>& keep) {
  std::vector<T> out;
  for (std::size_t i = 0; i < v.size(); ++i)
    if (keep[i]) out.push_back(v[i]);
  return out;
}

// Every tracked sample's response to its slide (core/sensor/tactip_identify.hpp), calibration split only.
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
    s.frames.back() = read_tactip_image((in / split / "images" / t.image).string(), frame.mirror);
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
      {"geometry_fit", tactip_geometry_fit_json(geometry, fit_options)},
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

int tactip_prior_min_calibration_samples() { return 2 * static_cast<int>(tactip_covariates(TactipTarget{}).size()); }

namespace {

// The import with the sensor's given values in `sensor`; `mirror_known`: whether its handedness is settled (given,
// or identified by a first pass), so that a mirrored camera is imported again with the images mirrored.
ImportReport import_tactip(const fs::path& in, const std::string& out_dir, const TactipImportOptions& options,
                           TactipSensor sensor, bool mirror_known) {
  const bool mirror = sensor.mirrored.value != 0;
  ImportReport report;
  std::vector<TactipTarget> cal_targets = read_split_targets(in, "calibration", options);
  const TactipRest rest = choose_tactip_rest(in, &cal_targets);
  const cv::Mat ref_img = read_tactip_image(rest.path, mirror);
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
  report.lines.push_back(tactip_geometry_fit_line(geometry, sensor));
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
  require_input_dir(in_dir);
  TactipSensor sensor = tactip_standard_defaults();
  if (!options.sensor_file.empty()) read_tactip_sensor_file(options.sensor_file, &sensor);
  return import_tactip(fs::path(in_dir), out_dir, options, sensor, sensor.mirrored.source == SensorValueSource::kGiven);
}

}  // namespace sb
