#include <catch2/catch.hpp>

#include "mini_grid.hpp"

#include <cmath>
#include <opencv2/imgproc.hpp>

#include "core/base/error.hpp"
#include "core/tracking/degrade.hpp"
#include "core/tracking/degrade_study.hpp"
#include "marker_render.hpp"

// This file's names in a namespace of its own: the unity build (CMAKE_UNITY_BUILD) compiles several
// test files as one translation unit.
namespace test_degrade {

using sbtest::kMiniMarkers;

using namespace sb;

namespace {

constexpr int kW = 320, kH = 240;

cv::Mat grey_frame(int value) { return cv::Mat(kH, kW, CV_8UC3, cv::Scalar(value, value, value)); }

Degradation make(DegradeKind kind, double strength, std::uint64_t seed = 1) { return {kind, strength, seed}; }

}  // namespace

TEST_CASE("degradations parse as KIND:STRENGTH with the range of their table entry", "[degrade]") {
  const Degradation d = parse_degradation("blur:2.5", "--degrade");
  CHECK(d.kind == DegradeKind::kBlur);
  CHECK(d.strength == 2.5);
  CHECK(degradation_label(d) == "blur:2.5");
  CHECK(parse_degradation("brightness:-0.6", "--degrade").strength == -0.6);
  CHECK_THROWS_WITH(parse_degradation("blur:11", "--degrade"),
                    Catch::Contains("[0, 10]") && Catch::Contains("--degrade"));
  CHECK_THROWS_AS(parse_degradation("fog:1", "--degrade"), InputError);
  CHECK_THROWS_AS(parse_degradation("blur", "--degrade"), InputError);
  CHECK_THROWS_AS(parse_degradation("blur:2x", "--degrade"), InputError);
  CHECK_THROWS_AS(parse_degradation("jpeg:0", "--degrade"), InputError);
  // Every kind has exactly one entry in the table, named as the kind.
  const ParamSet specs = degrade_param_specs();
  for (auto k : {DegradeKind::kBlur, DegradeKind::kNoise, DegradeKind::kBrightness, DegradeKind::kJpeg,
                 DegradeKind::kDrop, DegradeKind::kOcclusion})
    CHECK(specs.index_of(degrade_kind_name(k)) >= 0);
  CHECK(specs.size() == 6);
}

TEST_CASE("noise has the requested sigma and is the same for the same seed and frame", "[degrade]") {
  // On a flat 128 grey (far from 0 and 255, so no clipping), noisy - clean is the noise itself, rounded:
  // its standard deviation is sqrt(sigma^2 + 1/12) (rounding adds a uniform +-0.5). With 230400 samples
  // the estimate's relative standard error is 1/sqrt(2N) = 0.15 %; tolerance 2 %.
  constexpr double kSigma = 10, kRelTol = 0.02;
  const cv::Mat clean = grey_frame(128);
  const cv::Mat a = degrade_frame(clean, make(DegradeKind::kNoise, kSigma, 7), 3, 10);
  cv::Mat diff;
  cv::subtract(a, clean, diff, cv::noArray(), CV_32F);
  cv::Scalar mean, stddev;
  cv::meanStdDev(diff.reshape(1), mean, stddev);
  CHECK(stddev[0] == Approx(std::sqrt(kSigma * kSigma + 1.0 / 12)).epsilon(kRelTol));
  CHECK(std::abs(mean[0]) < 0.1);
  CHECK(cv::norm(a, degrade_frame(clean, make(DegradeKind::kNoise, kSigma, 7), 3, 10), cv::NORM_INF) == 0);
  CHECK(cv::norm(a, degrade_frame(clean, make(DegradeKind::kNoise, kSigma, 8), 3, 10), cv::NORM_INF) > 0);
  CHECK(cv::norm(a, degrade_frame(clean, make(DegradeKind::kNoise, kSigma, 7), 4, 10), cv::NORM_INF) > 0);
}

TEST_CASE("a brightness drift ramps the gain from 1 to 1 + strength over the clip", "[degrade]") {
  // gain(i) = 1 + s * i / (n - 1): with s = -0.5 and n = 11, frame 0 keeps 200, frame 10 gives 100,
  // frame 5 gives 200 * 0.75 = 150. With s = +1 the last frame saturates at 255.
  const cv::Mat clean = grey_frame(200);
  CHECK(degrade_frame(clean, make(DegradeKind::kBrightness, -0.5), 0, 11).at<cv::Vec3b>(5, 5)[0] == 200);
  CHECK(degrade_frame(clean, make(DegradeKind::kBrightness, -0.5), 5, 11).at<cv::Vec3b>(5, 5)[0] == 150);
  CHECK(degrade_frame(clean, make(DegradeKind::kBrightness, -0.5), 10, 11).at<cv::Vec3b>(5, 5)[0] == 100);
  CHECK(degrade_frame(clean, make(DegradeKind::kBrightness, 1.0), 10, 11).at<cv::Vec3b>(5, 5)[0] == 255);
}

TEST_CASE("blur is a Gaussian of the requested sigma", "[degrade]") {
  // A vertical step 0 | 255 at x = 160 (pixels < 160 dark). Blurred by sigma s, the profile at pixel x is
  // 255 * Phi((x - 159.5) / s); one sigma past the edge (x = 159.5 + s = 163.5 for s = 4) that is
  // 255 * Phi(1) = 255 * 0.8413 = 214.5. Tolerance: 1.5 grey levels (rounding, OpenCV's kernel truncation).
  constexpr double kSigma = 4, kTolGrey = 1.5;
  cv::Mat step = grey_frame(0);
  step(cv::Rect(160, 0, kW - 160, kH)).setTo(cv::Scalar(255, 255, 255));
  const cv::Mat b = degrade_frame(step, make(DegradeKind::kBlur, kSigma), 0, 1);
  // x = 163.5 lies between pixels 163 and 164: average them.
  const double at_one_sigma = 0.5 * (b.at<cv::Vec3b>(120, 163)[1] + b.at<cv::Vec3b>(120, 164)[1]);
  CHECK(at_one_sigma == Approx(255 * 0.841345).margin(kTolGrey));
  CHECK(b.at<cv::Vec3b>(120, 100)[1] == 0);  // 15 sigma away: untouched
  CHECK(b.at<cv::Vec3b>(120, 220)[1] == 255);
}

TEST_CASE("JPEG re-encoding loses more at lower quality", "[degrade]") {
  // A texture with edges (dots on a gradient) so the quantisation has something to lose.
  cv::Mat img(kH, kW, CV_8UC3);
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x)
      img.at<cv::Vec3b>(y, x) = cv::Vec3b(uchar(100 + x / 4), uchar(150), uchar(200 - y / 4));
  for (int y = 20; y < kH; y += 30)
    for (int x = 20; x < kW; x += 30) cv::circle(img, {x, y}, 5, cv::Scalar(40, 40, 40), cv::FILLED);
  auto loss = [&](double q) {
    return cv::norm(img, degrade_frame(img, make(DegradeKind::kJpeg, q), 0, 1), cv::NORM_L1) / img.total();
  };
  const double l95 = loss(95), l50 = loss(50), l5 = loss(5);
  CHECK(l95 < l50);
  CHECK(l50 < l5);
  CHECK(l5 > 3 * l95);
}

TEST_CASE("dropped frames: the rest window is kept, the count is the fraction, the choice is seeded", "[degrade]") {
  // 100 frames, 3 protected: round(0.5 * 97) = 49 dropped (lround rounds 48.5 away from zero), 51 kept.
  const auto kept = kept_frames(100, 0.5, 1, 3);
  REQUIRE(kept.size() == 51);
  CHECK(kept[0] == 0);
  CHECK(kept[1] == 1);
  CHECK(kept[2] == 2);
  CHECK(std::is_sorted(kept.begin(), kept.end()));
  CHECK(kept == kept_frames(100, 0.5, 1, 3));
  CHECK(kept != kept_frames(100, 0.5, 2, 3));
  CHECK(kept_frames(100, 0.0, 1, 3).size() == 100);

  std::vector<cv::Mat> frames;
  for (int i = 0; i < 20; ++i) frames.push_back(grey_frame(i));
  const DegradedClip clip = degrade_clip(frames, make(DegradeKind::kDrop, 0.5), 3);
  REQUIRE(clip.frames.size() == clip.source_frame.size());
  CHECK(clip.frames.size() == 20 - 9);  // round(0.5 * 17) = 9 dropped
  for (std::size_t k = 0; k < clip.frames.size(); ++k)
    CHECK(clip.frames[k].at<cv::Vec3b>(0, 0)[0] == clip.source_frame[k]);  // the frame is its source, unaltered
}

TEST_CASE("the occluder covers the requested area and crosses the image after the rest window", "[degrade]") {
  // Area fraction f = 0.1 of 320 x 240: radius r = sqrt(0.1 * 76800 / pi) = 27.65 px. Its centre moves
  // from u = -r (frame 0, outside) to 320 + r (last frame): in the middle frame of 21 (index 10) it is at
  // u = -r + 0.5 * (320 + 2r) = 160, fully inside, covering pi r^2 = 7680 pixels (+-1 % for the raster).
  constexpr double kF = 0.1, kAreaRelTol = 0.01;
  cv::Mat img(kH, kW, CV_8UC3);
  cv::randu(img, 0, 256);  // no pixel equals the fill by accident in more than a few places
  const Disc mid = occluder(kW, kH, kF, 10, 21);
  CHECK(mid.radius == Approx(std::sqrt(kF * kW * kH / M_PI)));
  CHECK(mid.u == Approx(160.0));
  CHECK(mid.v == Approx(119.5));
  auto changed = [&](int index) {
    cv::Mat d;
    cv::absdiff(img, degrade_frame(img, make(DegradeKind::kOcclusion, kF), index, 21), d);
    cv::cvtColor(d, d, cv::COLOR_BGR2GRAY);
    return cv::countNonZero(d);
  };
  CHECK(changed(0) == 0);
  CHECK(changed(10) == Approx(kF * kW * kH).epsilon(kAreaRelTol));
  CHECK(changed(20) == 0);
}

TEST_CASE("the score against the clean track counts lost markers and jumps onto a neighbour's dot", "[degrade]") {
  // Two markers 30 px apart (pitch 30), three frames, both still at rest in the clean track.
  // Degraded: frame 0 exact; frame 1 marker 0 lost (NaN) and marker 1 off by 3 px; frame 2 marker 0 sits
  // on marker 1's dot (error 30 px > 0.5 pitch = 15 px, nearest clean position is marker 1's: a jump onto
  // a neighbour) while marker 1 is exact.
  // Expected: marker-frames 6, lost 1, compared 5 with errors {0, 0, 3, 30, 0}: RMSE = sqrt(909 / 5) =
  // 13.483, max 30; jumps 1, onto a neighbour 1.
  TrackResult clean;
  clean.pitch_px = 30;
  clean.rest_px = {Vec2(10, 10), Vec2(40, 10)};
  clean.disp_px.assign(3, {Vec2::Zero(), Vec2::Zero()});
  TrackResult degraded = clean;
  degraded.disp_px[1][0] = Vec2(NAN, NAN);
  degraded.disp_px[1][1] = Vec2(3, 0);
  degraded.disp_px[2][0] = Vec2(30, 0);
  const DegradeScore s = compare_to_clean(clean, degraded, {0, 1, 2});
  CHECK(s.marker_frames == 6);
  CHECK(s.lost == 1);
  CHECK(s.compared == 5);
  CHECK(s.rmse_px == Approx(std::sqrt(909.0 / 5)));
  CHECK(s.max_px == Approx(30));
  CHECK(s.jumps == 1);
  CHECK(s.onto_neighbour == 1);
  REQUIRE(s.jump_events.size() == 1);
  CHECK(s.jump_events[0].source_frame == 2);
  CHECK(s.jump_events[0].onto_marker == 1);

  // Dropped frames: degraded frame k is source frame {0, 2}[k]; the degraded track's frame 1 is scored
  // against clean frame 2.
  TrackResult two = clean;
  two.disp_px = {clean.disp_px[0], clean.disp_px[2]};
  const DegradeScore d = compare_to_clean(clean, two, {0, 2});
  CHECK(d.frames_seen == 2);
  CHECK(d.marker_frames == 4);
  CHECK(d.jumps == 0);
  CHECK(d.max_px == 0);
}

TEST_CASE("a study on a synthetic clip: dropped frames score exactly, an occluder costs only hidden markers",
          "[degrade][tracker]") {
  // 7 x 9 dots drifting right by 1 px per frame after the rest window, 20 frames. Dropped frames (drop:0.5)
  // leave the kept frames' pixels as they were, so every marker tracked in both is at exactly its clean
  // position (error 0) and nothing jumps; the frames seen are 3 + (17 - round(8.5) = 8) = 11. The occluder
  // (occlusion:0.1, r = 27.6 px, crossing in 20 frames) hides some markers in some frames: lost > 0, still
  // no jump, and the markers kept are within kRimErrorPx (a dot cut by the disc's rim).
  constexpr double kRimErrorPx = 5.0;
  std::mt19937 rng(2);
  std::vector<cv::Mat> frames;
  for (int t = 0; t < 20; ++t) {
    std::vector<Vec2> c;
    for (const auto& p : sb::test::grid_7x9()) c.push_back(p + Vec2(std::max(0, t - 2), 0));
    frames.push_back(sb::test::render(c, rng));
  }
  const DegradeStudy study = run_degrade_study(
      frames, {parse_degradation("drop:0.5", "t"), parse_degradation("occlusion:0.1", "t")}, TrackerOptions{});
  REQUIRE(study.clean.markers() == kMiniMarkers);
  CHECK(study.clean.lost_fraction() == 0.0);
  REQUIRE(study.scores.size() == 2);
  const DegradeScore& drop = study.scores[0];
  CHECK(drop.label == "drop:0.5");
  CHECK(drop.frames_seen == 11);
  CHECK(drop.marker_frames == kMiniMarkers * 11);
  CHECK(drop.lost == 0);
  CHECK(drop.jumps == 0);
  CHECK(drop.max_px == 0.0);
  const DegradeScore& occ = study.scores[1];
  CHECK(occ.frames_seen == 20);
  CHECK(occ.lost > 0);
  CHECK(occ.jumps == 0);
  CHECK(occ.max_px < kRimErrorPx);
  CHECK(occ.compared + occ.lost == occ.marker_frames);
}

}  // namespace test_degrade
