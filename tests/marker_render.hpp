#pragma once
// Synthetic GelSight-like frames for the tracker tests: dark dots on a shaded colour background.
#include <opencv2/imgproc.hpp>
#include <random>
#include <vector>

#include "core/tracking/tracker.hpp"

namespace sb::test {

// Dots of radius 5 px (value 40) on a shaded colour gradient, blurred (sigma 1 px), with Gaussian pixel
// noise (sigma 3 grey levels; cv::theRNG, so a sequence is the same in every run of the binary from the
// same state). Sub-pixel centres through cv::circle's fixed-point shift.
inline cv::Mat render(const std::vector<Vec2>& centres, std::mt19937& rng) {
  constexpr int W = 320, H = 240, kShift = 8;
  cv::Mat img(H, W, CV_8UC3);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x)
      img.at<cv::Vec3b>(y, x) = cv::Vec3b(uchar(180 + 40 * x / W), 150, uchar(200 - 50 * y / H));
  for (const Vec2& c : centres)
    cv::circle(img, cv::Point(int(std::lround(c.x() * (1 << kShift))), int(std::lround(c.y() * (1 << kShift)))),
               5 << kShift, cv::Scalar(40, 40, 40), cv::FILLED, cv::LINE_AA, kShift);
  cv::GaussianBlur(img, img, {0, 0}, 1.0);
  cv::Mat noise(img.size(), CV_16SC3);
  cv::randn(noise, 0, 3);
  cv::Mat out;
  img.convertTo(out, CV_16SC3);
  out += noise;
  out.convertTo(img, CV_8UC3);
  (void)rng;
  return img;
}

// The twin_frames layout: 7 rows x 9 cols, pitch 33 px, first marker at (27.5, 20.5).
inline std::vector<Vec2> grid_7x9() {
  std::vector<Vec2> g;
  for (int r = 0; r < 7; ++r)
    for (int c = 0; c < 9; ++c) g.emplace_back(27.5 + 33 * c, 20.5 + 33 * r);
  return g;
}

// Index of the tracked marker whose rest is nearest `p`.
inline int nearest(const TrackResult& r, const Vec2& p) {
  int best = -1;
  double bd = 1e9;
  for (int i = 0; i < r.markers(); ++i)
    if ((r.rest_px[i] - p).norm() < bd) bd = (r.rest_px[i] - p).norm(), best = i;
  return best;
}

}  // namespace sb::test
