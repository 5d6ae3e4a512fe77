#pragma once
// Synthetic TacTip-like images for the pin tracker tests: white discs on black (already thresholded, as
// the tactip_shear images are) on a hexagonal lattice, displaced by a known smooth field.
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "core/geometry/pose.hpp"

namespace sb::test {

constexpr int kPinImagePx = 420;
constexpr double kPinPitchPx = 18.5;  // the real reference's pitch
constexpr double kPinRadiusPx = 6.0;  // area ~113 px^2 (the real median is 118)

// A hexagonal lattice of pitch kPinPitchPx inside a disc of radius `radius_px` about the image centre.
inline std::vector<Vec2> hex_disc_lattice(double radius_px = 170.0) {
  std::vector<Vec2> pts;
  const Vec2 c(0.5 * (kPinImagePx - 1), 0.5 * (kPinImagePx - 1));
  const double row = kPinPitchPx * std::sqrt(3.0) / 2.0;
  for (int r = -20; r <= 20; ++r)
    for (int q = -20; q <= 20; ++q) {
      const Vec2 p = c + Vec2(kPinPitchPx * (q + 0.5 * (r & 1)), row * r);
      if ((p - c).norm() <= radius_px) pts.push_back(p);
    }
  return pts;
}

// Filled white discs (no anti-aliasing, so the image is binary) at sub-pixel centres (cv::circle's
// fixed-point shift).
inline cv::Mat render_pins(const std::vector<Vec2>& centres) {
  constexpr int kShift = 4;
  cv::Mat img = cv::Mat::zeros(kPinImagePx, kPinImagePx, CV_8UC1);
  for (const Vec2& p : centres)
    cv::circle(img, cv::Point(int(std::lround(p.x() * (1 << kShift))), int(std::lround(p.y() * (1 << kShift)))),
               int(std::lround(kPinRadiusPx * (1 << kShift))), cv::Scalar(255), cv::FILLED, cv::LINE_8, kShift);
  return img;
}

// A press-like smooth field about the image centre c with Gaussian envelopes (length in pitches):
// a radial bulge s (r - c) exp(-|r - c|^2 / (2 (5 pitch)^2)), a slide t and a twist w (radians) that fade
// as exp(-|r - c|^2 / (2 (6 pitch)^2)): the skin is held at its base, so the rim moves least.
inline Vec2 press_field(const Vec2& r, double bulge, const Vec2& slide_px, double twist) {
  const Vec2 c(0.5 * (kPinImagePx - 1), 0.5 * (kPinImagePx - 1));
  const Vec2 x = r - c;
  const double g5 = std::exp(-x.squaredNorm() / (2 * std::pow(5 * kPinPitchPx, 2)));
  const double g6 = std::exp(-x.squaredNorm() / (2 * std::pow(6 * kPinPitchPx, 2)));
  return bulge * g5 * x + g6 * (slide_px + twist * Vec2(-x.y(), x.x()));
}

}  // namespace sb::test
