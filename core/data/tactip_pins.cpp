// A TacTip split's images read and their pins tracked and checked (tactip_pins.hpp).
#include "core/data/tactip_pins.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "core/base/error.hpp"
#include "core/base/format.hpp"

namespace fs = std::filesystem;

namespace sb {

// A grey image, mirrored left-right when the sensor says its camera sees the tool axes mirrored (so that E,
// whose x/y are the image's u/v, stays right-handed).
cv::Mat read_tactip_image(const std::string& path, bool mirror) {
  cv::Mat img = cv::imread(path, cv::IMREAD_GRAYSCALE);
  if (img.empty()) throw InputError(path, "cannot read image");
  if (mirror) cv::flip(img, img, 1);
  return img;
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
    const cv::Mat o = read_tactip_image(other_ref, mirror);
    if (o.size() != ref_img.size() || cv::norm(o, ref_img, cv::NORM_INF) != 0)
      report.lines.push_back(name + ": its image_0.png differs from calibration's rest; calibration's is the rest");
  }
  for (const auto& t : sp.targets) {
    const std::string ipath = (sdir / "images" / t.image).string();
    const cv::Mat img = read_tactip_image(ipath, mirror);
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

}  // namespace sb
