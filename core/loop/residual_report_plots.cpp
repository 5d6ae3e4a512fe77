// The residual loop's report as PNG plots, drawn with OpenCV (residual_report.hpp).
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <tuple>

#include "core/base/atomic_write.hpp"
#include "core/base/error.hpp"
#include "core/base/format.hpp"
#include "core/loop/residual_report.hpp"
#include "core/loop/residual_report_format.hpp"

namespace sb {

namespace {

const cv::Scalar kInk(40, 40, 40), kGrid(215, 215, 215), kBlue(200, 90, 30), kRed(40, 40, 210), kGrey(150, 150, 150);

void text(cv::Mat& img, const std::string& s, cv::Point p, double scale = 0.45, const cv::Scalar& c = kInk) {
  cv::putText(img, s, p, cv::FONT_HERSHEY_SIMPLEX, scale, c, 1, cv::LINE_AA);
}

// RMS vs covariate: before (blue) and after (red) lines over the bins.
cv::Mat covariate_plot(const CovariateTable& before, const CovariateTable* after) {
  const int W = 480, H = 300, L = 60, R = 20, T = 30, B = 55;
  cv::Mat img(H, W, CV_8UC3, cv::Scalar(255, 255, 255));
  double ymax = 0;
  for (double v : before.rms_px) ymax = std::isfinite(v) ? std::max(ymax, v) : ymax;
  if (after)
    for (double v : after->rms_px) ymax = std::isfinite(v) ? std::max(ymax, v) : ymax;
  ymax = ymax > 0 ? 1.1 * ymax : 1.0;
  const int n = static_cast<int>(before.labels.size());
  const auto px = [&](int b) { return L + (n <= 1 ? 0 : (W - L - R) * b / (n - 1)); };
  const auto py = [&](double v) { return static_cast<int>(H - B - (H - T - B) * v / ymax); };
  for (int g = 0; g <= 4; ++g) {
    const double v = ymax * g / 4;
    cv::line(img, {L, py(v)}, {W - R, py(v)}, kGrid);
    text(img, report_format::g3(v), {5, py(v) + 4}, 0.4);
  }
  cv::rectangle(img, {L, T}, {W - R, H - B}, kInk);
  const auto series = [&](const CovariateTable& t, const cv::Scalar& c) {
    cv::Point prev(-1, -1);
    for (int b = 0; b < n; ++b) {
      if (!std::isfinite(t.rms_px[b])) {
        prev = {-1, -1};
        continue;
      }
      const cv::Point p(px(b), py(t.rms_px[b]));
      cv::circle(img, p, 3, c, cv::FILLED, cv::LINE_AA);
      if (prev.x >= 0) cv::line(img, prev, p, c, 2, cv::LINE_AA);
      prev = p;
    }
  };
  series(before, kBlue);
  if (after) series(*after, kRed);
  for (int b = 0; b < n; ++b) {
    const std::string lab = before.unit.empty() ? before.labels[b] : report_format::g3(before.centre[b]);
    text(img, lab, {px(b) - 14, H - B + 16}, 0.38);
  }
  text(img, before.name + (before.unit.empty() ? "" : " (" + before.unit + ")"), {L, H - 12}, 0.5);
  text(img, "residual RMS (px)", {L, T - 10}, 0.5);
  text(img, "before", {W - 150, T - 10}, 0.45, kBlue);
  if (after) text(img, "after", {W - 80, T - 10}, 0.45, kRed);
  return img;
}

// Arrows of a per-marker field at the markers' image positions, scaled so the longest is 0.8 pitch (or, with
// `longest_px` > 0, an arrow that long: one scale for panels that are compared).
cv::Mat quiver_plot(const Sensor& sensor, const std::vector<Vec2>& field, const std::string& title,
                    double longest_px = 0) {
  const int S = 2, top = 40;
  const int W = sensor.camera.width_px * S, H = sensor.camera.height_px * S + top;
  cv::Mat img(H, W, CV_8UC3, cv::Scalar(255, 255, 255));
  double longest = 0;
  for (const auto& v : field) longest = std::max(longest, v.norm());
  if (longest_px > 0) longest = longest_px;
  double pitch = std::numeric_limits<double>::infinity();
  const auto& m = sensor.markers_rest_px;
  for (std::size_t i = 1; i < m.size(); ++i) pitch = std::min(pitch, (m[i] - m[0]).norm());
  if (!std::isfinite(pitch) || pitch <= 0) pitch = 30;
  const double gain = longest > 0 ? 0.8 * pitch / longest : 0.0;
  for (std::size_t i = 0; i < m.size(); ++i) {
    const cv::Point2d p(m[i].x() * S, m[i].y() * S + top);
    cv::circle(img, p, 2, kGrey, cv::FILLED, cv::LINE_AA);
    const cv::Point2d q = p + cv::Point2d(field[i].x(), field[i].y()) * gain * S;
    if (field[i].norm() * gain > 0.5) cv::arrowedLine(img, p, q, kRed, 2, cv::LINE_AA, 0, 0.25);
  }
  text(img, title, {10, 18}, 0.55);
  text(img, "longest arrow = " + report_format::g3(longest) + " px (drawn x" + report_format::g3(gain) + ")", {10, 34},
       0.45, kGrey);
  return img;
}

void write_png(const std::string& path, const cv::Mat& img) {
  std::vector<unsigned char> buf;
  if (!cv::imencode(".png", img, buf)) throw InputError(path, "could not encode the plot");
  write_file_atomic(path, std::string(buf.begin(), buf.end()));
}

std::string slug(const std::string& s) {
  std::string o;
  for (char c : s) o += std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
  return o;
}

// One row of quiver panels, a bin each, on one arrow scale (the longest mean arrow of any bin), halved in size.
cv::Mat binned_fields_plot(const Sensor& sensor, const BinnedMeanFields& b, const std::string& model_id) {
  double longest = 0;
  for (const auto& field : b.mean_px)
    for (const auto& v : field) longest = std::max(longest, v.norm());
  std::vector<cv::Mat> panels;
  for (std::size_t k = 0; k < b.labels.size(); ++k) {
    const std::string title = b.name + ": " + b.labels[k] + " (" + std::to_string(b.frames[k]) + " frames)";
    cv::Mat panel = quiver_plot(sensor, b.mean_px[k], title, longest);
    cv::resize(panel, panel, cv::Size(), 0.5, 0.5, cv::INTER_AREA);
    panels.push_back(panel);
  }
  cv::Mat row;
  cv::hconcat(panels, row);
  cv::Mat header(28, row.cols, row.type(), cv::Scalar(255, 255, 255));
  text(header, "mean residual (measured - " + model_id + ") per bin of " + b.name + "; one arrow scale", {10, 19}, 0.5);
  cv::Mat out;
  cv::vconcat(header, row, out);
  return out;
}

}  // namespace

std::vector<std::string> write_residual_plots(const ResidualReport& r, const std::string& dir,
                                              const std::string& stem) {
  std::vector<std::string> names;
  const bool changed = r.after_model != r.model_id;
  for (std::size_t c = 0; c < r.structure_before.covariates.size(); ++c) {
    const auto& t = r.structure_before.covariates[c];
    const CovariateTable* after = changed && c < r.structure_after.covariates.size() ? &r.structure_after.covariates[c]
                                                                                     : nullptr;
    // The after table has its own bin edges; plot it only when they match the before table's.
    if (after && after->labels != t.labels) after = nullptr;
    const std::string name = stem + "_rms_vs_" + slug(t.name) + ".png";
    write_png((std::filesystem::path(dir) / name).string(), covariate_plot(t, after));
    names.push_back(name);
  }
  const auto pc1_title = [](const ResidualStructure& s) {
    return " PC1 (" + report_format::f3(100 * (s.explained_variance.empty() ? 0.0 : s.explained_variance[0])) +
           " % of variance)";
  };
  const std::vector<std::tuple<std::string, const ResidualStructure*, std::string>> fields = {
      {"mean_residual", &r.structure_before, "mean residual (measured - " + r.model_id + ")"},
      {"pc1", &r.structure_before, "residual" + pc1_title(r.structure_before)},
      {"mean_residual_after", &r.structure_after, "mean residual (measured - " + r.after_model + ")"}};
  for (const auto& [suffix, structure, title] : fields) {
    if (structure == &r.structure_after && !changed) continue;
    const std::string name = stem + "_" + suffix + ".png";
    write_png((std::filesystem::path(dir) / name).string(),
              quiver_plot(*r.sensor, suffix == "pc1" ? structure->pc1_px : structure->mean_field_px, title));
    names.push_back(name);
  }
  for (const auto& [structure, model, suffix] :
       {std::tuple{&r.structure_before, r.model_id, std::string()},
        std::tuple{&r.structure_after, r.after_model, std::string("_after")}}) {
    if (structure == &r.structure_after && !changed) continue;
    for (const auto& b : structure->binned_fields) {
      if (b.labels.empty()) continue;
      const std::string name = stem + "_mean_by_" + slug(b.name.substr(0, b.name.find(" ("))) + suffix + ".png";
      write_png((std::filesystem::path(dir) / name).string(), binned_fields_plot(*r.sensor, b, model));
      names.push_back(name);
    }
  }
  return names;
}

}  // namespace sb
