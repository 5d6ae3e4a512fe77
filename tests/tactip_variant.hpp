#pragma once
// Development data for a new TacTip: a copy of raw/tactip_shear (a subset of its rows) changed the way another
// sensor instance or lab set-up would present it, written into a folder for the importer, which is not told
// what was changed. Shared by tests/test_tactip_variants.cpp and bench/bench_tactip.cpp.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <random>
#include <sstream>
#include <string>
#include <vector>

namespace sbtest {

struct TactipVariant {
  int samples = 150;                      // rows kept per split (the first ones)
  double rotate_deg = 0;                  // the images turned about their centre (OpenCV's sense: counter-clockwise on
                                          // screen, so the image-from-tool angle drops by it)
  double scale = 1;                       // the images magnified about their centre
  int width_px = 0, height_px = 0;        // the crop (0: the source's)
  double shift_u_px = 0, shift_v_px = 0;  // the crop's centre moved by this (the content moves by minus it)
  bool drop_reference = false;            // no images/image_0.png
  double press_offset_mm = 0;             // added to every pose_z (the tool's zero above the touch)
  int out_of_contact = 0;  // copies of the reference added as presses short of the touch (depth < offset)
  bool sort_by_depth = false;
  bool crlf_bom = false;         // targets.csv with CRLF line ends and a UTF-8 byte-order mark
  bool reorder_columns = false;  // the columns reversed and one more appended
};

// A second sensor as the held-out TacTip presents itself: magnified 1.06, turned 17 deg, cropped to 445 x 440 px,
// no images/image_0.png, the press depths 0.8 mm deeper with 12 presses short of the touch, rows sorted by depth,
// targets.csv with CRLF, a BOM, reordered and extra columns.
inline TactipVariant held_out_like_variant(int samples) {
  TactipVariant v;
  v.samples = samples;
  v.scale = 1.06;
  v.rotate_deg = 17;
  v.width_px = 445;
  v.height_px = 440;
  v.drop_reference = true;
  v.press_offset_mm = 0.8;
  v.out_of_contact = 12;
  v.sort_by_depth = true;
  v.crlf_bom = true;
  v.reorder_columns = true;
  return v;
}

// The image transform of a variant: rotation and scale about the source's centre, onto the new crop.
inline cv::Mat variant_image(const cv::Mat& src, const TactipVariant& v) {
  const cv::Size out(v.width_px > 0 ? v.width_px : src.cols, v.height_px > 0 ? v.height_px : src.rows);
  const cv::Point2f c((src.cols - 1) / 2.0F, (src.rows - 1) / 2.0F);
  cv::Mat M = cv::getRotationMatrix2D(c, v.rotate_deg, v.scale);
  M.at<double>(0, 2) += (out.width - 1) / 2.0 - c.x - v.shift_u_px;
  M.at<double>(1, 2) += (out.height - 1) / 2.0 - c.y - v.shift_v_px;
  cv::Mat dst;
  cv::warpAffine(src, dst, M, out, cv::INTER_LINEAR, cv::BORDER_CONSTANT, cv::Scalar(0));
  cv::threshold(dst, dst, 127, 255, cv::THRESH_BINARY);  // the source is thresholded: keep it black and white
  return dst;
}

// Where a source pixel lands in the variant's image.
inline cv::Point2d variant_px(const cv::Point2d& p, const cv::Size& src, const TactipVariant& v) {
  const cv::Size out(v.width_px > 0 ? v.width_px : src.width, v.height_px > 0 ? v.height_px : src.height);
  const cv::Point2d c((src.width - 1) / 2.0, (src.height - 1) / 2.0);
  const double a = -v.rotate_deg * M_PI / 180.0;  // OpenCV's angle is counter-clockwise on screen (v down)
  const cv::Point2d d = p - c;
  const cv::Point2d r(v.scale * (std::cos(a) * d.x - std::sin(a) * d.y),
                      v.scale * (std::sin(a) * d.x + std::cos(a) * d.y));
  return r + cv::Point2d((out.width - 1) / 2.0 - v.shift_u_px, (out.height - 1) / 2.0 - v.shift_v_px);
}

namespace detail {
inline std::vector<std::string> split_csv(const std::string& line) {
  std::vector<std::string> c;
  std::stringstream ss(line);
  for (std::string x; std::getline(ss, x, ',');) c.push_back(x);
  return c;
}
inline std::string join_csv(const std::vector<std::string>& c) {
  std::string s;
  for (std::size_t k = 0; k < c.size(); ++k) s += (k ? "," : "") + c[k];
  return s;
}
}  // namespace detail

// Writes the variant of `src` (raw/tactip_shear) into `dst` (replaced).
inline void write_tactip_variant(const std::filesystem::path& src, const std::filesystem::path& dst,
                                 const TactipVariant& v) {
  namespace fs = std::filesystem;
  fs::remove_all(dst);
  std::mt19937 rng(7);
  for (const char* split : {"calibration", "validation"}) {
    fs::create_directories(dst / split / "images");
    for (const auto& e : fs::directory_iterator(src / split))
      if (e.is_regular_file() && e.path().extension() == ".json")
        fs::copy_file(e.path(), dst / split / e.path().filename());
    std::ifstream in(src / split / "targets.csv");
    std::string line;
    std::getline(in, line);
    const std::vector<std::string> header = detail::split_csv(line);
    const std::size_t cz = std::find(header.begin(), header.end(), "pose_z") - header.begin();
    const std::size_t ci = std::find(header.begin(), header.end(), "sensor_image") - header.begin();
    std::vector<std::vector<std::string>> rows;
    int max_number = 0;
    while (int(rows.size()) < v.samples && std::getline(in, line)) {
      if (!line.empty() && line.back() == '\r') line.pop_back();
      if (line.empty()) continue;
      rows.push_back(detail::split_csv(line));
      int n = 0;
      std::sscanf(rows.back()[ci].c_str(), "image_%d.png", &n);
      max_number = std::max(max_number, n);
    }
    const cv::Mat ref = cv::imread((src / split / "images" / "image_0.png").string(), cv::IMREAD_GRAYSCALE);
    for (auto& r : rows) {
      const cv::Mat img = cv::imread((src / split / "images" / r[ci]).string(), cv::IMREAD_GRAYSCALE);
      cv::imwrite((dst / split / "images" / r[ci]).string(), variant_image(img, v));
      r[cz] = std::to_string(std::stod(r[cz]) + v.press_offset_mm);
    }
    if (!v.drop_reference) cv::imwrite((dst / split / "images" / "image_0.png").string(), variant_image(ref, v));
    // Presses short of the touch: the reference's image at a depth below the offset, with a slide (within 4 mm,
    // inside the source's 5 mm disk) and a tilt.
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (int k = 0; k < v.out_of_contact; ++k) {
      std::vector<std::string> r(header.size(), "0");
      r[ci] = "image_" + std::to_string(max_number + 1 + k) + ".png";
      const double phi = M_PI * u(rng), slide = 2.0 + 2.0 * u(rng);
      for (std::size_t c = 0; c < header.size(); ++c) {
        if (header[c] == "object_label") r[c] = "surface";
        if (header[c] == "shear_x") r[c] = std::to_string(slide * std::cos(phi));
        if (header[c] == "shear_y") r[c] = std::to_string(slide * std::sin(phi));
        if (header[c] == "pose_Rx" || header[c] == "pose_Ry") r[c] = std::to_string(15.0 * u(rng));
      }
      r[cz] = std::to_string(v.press_offset_mm * (0.3 + 0.6 * (k + 0.5) / v.out_of_contact));
      cv::imwrite((dst / split / "images" / r[ci]).string(), variant_image(ref, v));
      rows.push_back(r);
    }
    if (v.sort_by_depth)
      std::stable_sort(rows.begin(), rows.end(),
                       [&](const auto& a, const auto& b) { return std::stod(a[cz]) < std::stod(b[cz]); });
    std::vector<std::size_t> order(header.size());
    for (std::size_t c = 0; c < order.size(); ++c) order[c] = v.reorder_columns ? order.size() - 1 - c : c;
    auto arrange = [&](const std::vector<std::string>& r, const std::string& extra) {
      std::vector<std::string> o;
      for (std::size_t c : order) o.push_back(r[c]);
      if (v.reorder_columns) o.push_back(extra);
      return detail::join_csv(o);
    };
    const std::string eol = v.crlf_bom ? "\r\n" : "\n";
    std::ofstream out(dst / split / "targets.csv", std::ios::binary);
    if (v.crlf_bom) out << "\xEF\xBB\xBF";
    out << arrange(header, "note") << eol;
    for (const auto& r : rows) out << arrange(r, "x") << eol;
  }
}

}  // namespace sbtest
