// The tracker under the hard cases of degraded video: a step larger than the matching can resolve
// (dropped frames during a fast press) and an occluder sliding over the dots. A marker may be lost; it
// must never be given another marker's dot.
#include <catch2/catch.hpp>

#include "mini_grid.hpp"

#include <cmath>
#include <opencv2/imgproc.hpp>
#include <random>

#include "core/tracking/degrade.hpp"
#include "core/tracking/tracker.hpp"
#include "marker_render.hpp"

// This file's names in a namespace of its own: the unity build (CMAKE_UNITY_BUILD) compiles several
// test files as one translation unit.
namespace test_tracker_degrade {

using sbtest::kMiniMarkers;

using namespace sb;
using sb::test::grid_7x9;
using sb::test::nearest;
using sb::test::render;

namespace {

constexpr double kPitchPx = 33;  // grid_7x9

// du(p) = amplitude * exp(-|p - c|^2 / (2 w^2)) along u, c = image centre: a press that drags the gel.
Vec2 bump(const Vec2& p, double amplitude, double width) {
  const Vec2 c(159.5, 119.5);
  return Vec2(amplitude * std::exp(-(p - c).squaredNorm() / (2 * width * width)), 0.0);
}

}  // namespace

TEST_CASE("dropped frames during a fast drag: markers are lost, never moved onto a neighbour's dot, then re-acquired",
          "[tracker][degrade]") {
  // Frames 0-2 at rest; frame 3 jumps to a wide bump (w = 100 px) of amplitude A (the frames in between were
  // dropped); frames 4-11 grow it slowly (+0.5 px per frame at the centre).
  // Why it is hard: with no velocity yet, every marker is predicted at rest. A marker that moved d = A
  // has its own dot at distance A and its left neighbour's (which moved d' ~ A) at 33 - d'. For
  // A = 24 px the neighbour's dot is nearer (about 9 px, inside the 0.45-pitch gate of 14.85 px; the own
  // dot at 24 px is outside it): a nearest-dot tracker moves the whole central block one pitch left, a
  // consistent-looking field 33 px off. For A = 20 px the two distances are 13 and 20 px: ambiguous.
  // Expected: every finite displacement within kMaxErrorPx of the truth (a neighbour's dot is 33 px off),
  // and once the motion is slow again (from frame 6) every marker tracked.
  constexpr double kWidthPx = 100, kMaxErrorPx = 1.0;
  const double amplitude = GENERATE(20.0, 24.0);
  INFO("amplitude " << amplitude << " px = " << amplitude / kPitchPx << " pitch");
  const auto rest = grid_7x9();
  auto truth = [&](const Vec2& p, int t) {
    return t < 3 ? Vec2::Zero() : bump(p, amplitude + 0.5 * (t - 3), kWidthPx);
  };
  std::mt19937 rng(11);
  constexpr int kFrames = 12, kSettledFrom = 6;
  std::vector<cv::Mat> frames;
  for (int t = 0; t < kFrames; ++t) {
    std::vector<Vec2> c;
    for (const auto& p : rest) c.push_back(p + truth(p, t));
    frames.push_back(render(c, rng));
  }
  const TrackResult r = track_frames(frames, TrackerOptions{});
  REQUIRE(r.markers() == kMiniMarkers);
  int wrong = 0, lost_after_settling = 0;
  double worst = 0;
  for (const auto& p : rest) {
    const int m = nearest(r, p);
    for (int t = 0; t < kFrames; ++t) {
      const Vec2 d = r.disp_px[t][m];
      if (!std::isfinite(d.x())) {
        lost_after_settling += t >= kSettledFrom ? 1 : 0;
        continue;
      }
      const double e = (d - truth(p, t)).norm();
      worst = std::max(worst, e);
      wrong += e > kMaxErrorPx ? 1 : 0;
    }
  }
  CHECK(wrong == 0);
  CHECK(worst < kMaxErrorPx);
  CHECK(lost_after_settling == 0);
  // The step really was beyond the gate for the centre marker (not a trivially small motion).
  CHECK(truth(Vec2(159.5, 119.5), 3).x() > TrackerOptions{}.gate_fraction * kPitchPx);
}

TEST_CASE("an occluder sliding over moving dots: hidden markers are lost, visible ones right, all back after it",
          "[tracker][degrade]") {
  // After the rest window (frames 0-2, whose median is the rest), the gel drifts right by 0.5 px per frame
  // (uniform) while degrade_frame's occluder, a disc of 8 % of
  // the image (r = sqrt(0.08 * 76800 / pi) = 44.2 px) in the frame's mean colour, crosses from u = -r to
  // 320 + r over the 40 frames (11.3 px per frame). The disc's colour differs from the shaded background
  // around it, so its rim is itself a faint dark or bright edge the detector may see.
  // (An earlier tracker passes it as well: a regression guard for the lost-marker prediction.)
  // Expected, for each marker and frame, with its dot centre at distance D from the disc centre and dot
  // radius 5 px (+1 px for the blur): D < r - 6: the dot is hidden, the marker must be lost (NaN);
  // D > r + 6: fully visible, the marker must be tracked within kMaxErrorPx; in between (a partly hidden
  // dot) either lost or within kRimErrorPx (the centroid of the visible part of a dot moves by at most
  // its radius). After the disc has left (last frame) every marker is tracked within kMaxErrorPx.
  constexpr double kFraction = 0.08, kDriftPxPerFrame = 0.5, kDotPx = 6, kMaxErrorPx = 0.5, kRimErrorPx = 5.0;
  constexpr int kFrames = 40;
  const auto rest = grid_7x9();
  std::mt19937 rng(5);
  const Degradation occlusion{DegradeKind::kOcclusion, kFraction, 1};
  auto drift = [&](int t) { return Vec2(kDriftPxPerFrame * std::max(0, t - 2), 0); };
  std::vector<cv::Mat> frames;
  for (int t = 0; t < kFrames; ++t) {
    std::vector<Vec2> c;
    for (const auto& p : rest) c.push_back(p + drift(t));
    frames.push_back(degrade_frame(render(c, rng), occlusion, t, kFrames));
  }
  const TrackResult r = track_frames(frames, TrackerOptions{});
  REQUIRE(r.markers() == kMiniMarkers);
  int hidden_but_tracked = 0, visible_but_lost = 0, visible_wrong = 0, rim_wrong = 0;
  for (int t = 0; t < kFrames; ++t) {
    const Disc disc = occluder(320, 240, kFraction, t, kFrames);
    for (const auto& p : rest) {
      const Vec2 truth = drift(t);
      const Vec2 centre = p + truth;
      const double dist = (centre - Vec2(disc.u, disc.v)).norm();
      const Vec2 d = r.disp_px[t][nearest(r, p)];
      const bool tracked = std::isfinite(d.x());
      const double e = tracked ? (d - truth).norm() : 0.0;
      if (dist < disc.radius - kDotPx) {
        hidden_but_tracked += tracked ? 1 : 0;
      } else if (dist > disc.radius + kDotPx) {
        visible_but_lost += tracked ? 0 : 1;
        visible_wrong += e > kMaxErrorPx ? 1 : 0;
      } else {
        rim_wrong += e > kRimErrorPx ? 1 : 0;
      }
    }
  }
  CHECK(hidden_but_tracked == 0);
  CHECK(visible_wrong == 0);
  CHECK(rim_wrong == 0);
  CHECK(visible_but_lost == 0);
  for (const auto& p : rest) {
    const Vec2 d = r.disp_px.back()[nearest(r, p)];
    REQUIRE(std::isfinite(d.x()));
    CHECK((d - drift(kFrames - 1)).norm() < kMaxErrorPx);
  }
}

TEST_CASE("a press grows under an occluder: revealed markers are lost until re-acquired, never on a neighbour's dot",
          "[tracker][degrade]") {
  // A disc of radius 75 px in the frame's mean colour sits on the image centre over frames 4-23 and is then
  // lifted. Under it, after the rest window, a bump (w = 45 px) grows by 1.3 px per frame to A = 26 px
  // (frame 22) and stays. The disc hides every marker within 75 - 6 px of the centre: the centre, its
  // 8-neighbourhood (33 and 46.7 px) and the 4 at 66 px, so the centre has no tracked neighbour left and
  // nothing tells the tracker how far the gel moved while it was hidden. Visible around the disc, the ring
  // at 73.8 px moved only 26 exp(-73.8^2 / (2 45^2)) = 6.8 px.
  // Why it is hard: when the disc lifts, a marker predicted at its rest (or at the ring's 6.8 px) finds the
  // dot of its left neighbour (moved 26 exp(-33^2 / (2 45^2)) = 19.8 px, now at -13.2 px) as near as its
  // own (at +26 px): taking the nearest dot moves the centre one pitch left. (An earlier tracker
  // passes this case too, narrowly: the neighbour, predicted from the visible ring, claims its own dot
  // 13.0 px away first. It guards the ring-by-ring prediction and growth against that regression.)
  // Expected: every finite displacement within kMaxErrorPx of the truth (kRimErrorPx for a dot the disc's
  // rim cuts: the centroid of its visible part moves by at most its 5 px radius; a neighbour's dot is
  // 33 - 19.8 = 13 px or more off), every hidden marker lost while hidden, and every marker tracked again
  // within kReacquireFrames of the lift.
  constexpr double kAmplitudePx = 26, kWidthPx = 45, kRadiusPx = 75, kDotPx = 6, kMaxErrorPx = 1.0, kRimErrorPx = 5.0;
  constexpr int kCoverFrom = 4, kLiftAt = 24, kFrames = 34, kReacquireFrames = 6;
  const Vec2 centre(159.5, 119.5);
  const auto rest = grid_7x9();
  auto truth = [&](const Vec2& p, int t) {
    return bump(p, std::min(kAmplitudePx, 1.3 * std::max(0, t - 2)), kWidthPx);
  };
  std::mt19937 rng(9);
  std::vector<cv::Mat> frames;
  for (int t = 0; t < kFrames; ++t) {
    std::vector<Vec2> c;
    for (const auto& p : rest) c.push_back(p + truth(p, t));
    cv::Mat img = render(c, rng);
    if (t >= kCoverFrom && t < kLiftAt) cv::circle(img, cv::Point(160, 120), int(kRadiusPx), cv::mean(img), cv::FILLED);
    frames.push_back(img);
  }
  const TrackResult r = track_frames(frames, TrackerOptions{});
  REQUIRE(r.markers() == kMiniMarkers);
  int wrong = 0, hidden_but_tracked = 0, lost_late = 0;
  double worst = 0;
  for (const auto& p : rest) {
    const int m = nearest(r, p);
    for (int t = 0; t < kFrames; ++t) {
      const Vec2 d = r.disp_px[t][m];
      const bool covered = t >= kCoverFrom && t < kLiftAt;
      const double dist = (p + truth(p, t) - centre).norm();
      const bool hidden = covered && dist < kRadiusPx - kDotPx;
      const bool rim = covered && !hidden && dist < kRadiusPx + kDotPx;
      if (!std::isfinite(d.x())) {
        lost_late += t >= kLiftAt + kReacquireFrames ? 1 : 0;
        continue;
      }
      hidden_but_tracked += hidden ? 1 : 0;
      const double e = (d - truth(p, t)).norm();
      if (!rim) worst = std::max(worst, e);
      wrong += e > (rim ? kRimErrorPx : kMaxErrorPx) ? 1 : 0;
    }
  }
  CHECK(hidden_but_tracked == 0);
  CHECK(wrong == 0);
  CHECK(worst < kMaxErrorPx);
  CHECK(lost_late == 0);
  // The centre really moved beyond the gate while hidden.
  CHECK(truth(centre, kLiftAt).x() > TrackerOptions{}.gate_fraction * kPitchPx);
}

}  // namespace test_tracker_degrade
