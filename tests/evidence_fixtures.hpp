#pragma once
// Synthetic splits for the evidence readers (core/loop/evidence.hpp): presses and slides on the default sensor's
// 7 x 9 marker grid (33 px pitch), with a model field of known shape and a measured field built from it by hand.
#include <algorithm>
#include <cmath>
#include <functional>
#include <random>

#include "core/loop/evidence.hpp"
#include "core/sensor/sensor.hpp"

namespace sbtest {

inline const sb::Sensor& evidence_sensor() {
  static const sb::Sensor s = sb::make_default_sensor();
  return s;
}

// One frame as the builder sees it: the recorded depth (m), whether in contact, the contact centre (px), its
// travel since first contact (px).
struct FrameSpec {
  double depth_m = 0;
  bool in_contact = false;
  sb::Vec2 centre_px = sb::Vec2::Zero();
  double travel_px = 0;
  sb::Vec2 slide_px = sb::Vec2::Zero();     // the indenter's lateral travel since first contact (px of E's xy)
  sb::Vec2 approach_xy = sb::Vec2::Zero();  // (R_EI z)_xy: the tilt's sine along its direction
};

// The model's field of a press about `centre`: `amp` px along the outward radius at one Gaussian width (2 pitches)
// from the centre, exp(-r^2 / (2 w^2)) r / w, plus a uniform `shear` px along the slide (the slide's direction).
inline sb::Vec2 press_field(const sb::Vec2& m, const sb::Vec2& centre, double amp, const sb::Vec2& shear) {
  constexpr double kWidthPx = 66.0;
  const sb::Vec2 d = m - centre;
  const double g = std::exp(-d.squaredNorm() / (2 * kWidthPx * kWidthPx));
  return g * (amp * d / kWidthPx + shear);
}

// A split of `n` samples: frames from `frames(sample)`, the model field pred(sample, frame, marker), the measured
// field meas(sample, frame, marker, pred) plus Gaussian noise of `noise_px` (seeded by `seed`).
using FramesOf = std::function<std::vector<FrameSpec>(int sample)>;
using PredOf = std::function<sb::Vec2(int sample, const FrameSpec& f, std::size_t marker)>;
using MeasOf = std::function<sb::Vec2(int sample, const FrameSpec& f, std::size_t marker, const sb::Vec2& pred)>;
using MarkerDepthOf = std::function<double(const FrameSpec& f, std::size_t marker)>;

inline sb::EvidenceSplit make_split(int n, const FramesOf& frames, const PredOf& pred, const MeasOf& meas,
                                    double noise_px, std::uint64_t seed, const MarkerDepthOf& marker_depth = {}) {
  const sb::Sensor& s = evidence_sensor();
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, noise_px);
  sb::EvidenceSplit split;
  split.noise_px = noise_px;
  for (int i = 0; i < n; ++i) {
    sb::EvidenceSample e;
    for (const FrameSpec& f : frames(i)) {
      std::vector<sb::Vec2> p, m;
      std::vector<double> h;
      for (std::size_t j = 0; j < s.markers_rest_px.size(); ++j) {
        p.push_back(pred(i, f, j));
        const double dx = noise(rng);  // sequenced: argument order is unspecified
        m.push_back(meas(i, f, j, p.back()) + sb::Vec2(dx, noise(rng)));
        if (marker_depth) h.push_back(f.in_contact ? marker_depth(f, j) : 0.0);
      }
      e.fp.pred_px.push_back(p);
      e.fp.meas_px.push_back(m);
      e.fp.in_contact.push_back(f.in_contact ? 1 : 0);
      e.fp.held.push_back(0);
      e.fp.contact_centre_px.push_back(f.centre_px);
      e.fp.travel_px.push_back(f.travel_px);
      e.depth_m.push_back(f.depth_m);
      e.tilt_rad.push_back(std::asin(std::min(1.0, f.approach_xy.norm())));
      e.approach_xy.push_back(f.approach_xy);
      e.slide_m.push_back(f.slide_px * s.camera.metres_per_px());
      if (marker_depth) e.marker_depth_m.push_back(h);
    }
    split.samples.push_back(std::move(e));
  }
  return split;
}

// The grid's centre (px), where the default camera's principal point is.
inline sb::Vec2 grid_centre() { return evidence_sensor().camera.principal_px; }

// A press from rest at `centre`: `rest` frames out of contact, then `ramp` frames to `deepest_m` in even steps.
inline std::vector<FrameSpec> press_frames(const sb::Vec2& centre, double deepest_m, int rest = 5, int ramp = 10) {
  std::vector<FrameSpec> out;
  for (int k = 0; k < rest; ++k) out.push_back({0, false, centre, 0});
  for (int k = 1; k <= ramp; ++k) out.push_back({deepest_m * k / ramp, true, centre, 0});
  return out;
}

// A press to `depth_m` at `start` and a slide of `travel_px` along `dir` in `steps` frames.
inline std::vector<FrameSpec> slide_frames(const sb::Vec2& start, const sb::Vec2& dir, double depth_m, double travel_px,
                                           int steps = 10) {
  std::vector<FrameSpec> out = press_frames(start, depth_m, 3, 4);
  for (int k = 1; k <= steps; ++k) {
    const double t = travel_px * k / steps;
    out.push_back({depth_m, true, start + t * dir.normalized(), t, t * dir.normalized()});
  }
  return out;
}

// No fitted parameter (the sign check is off).
inline double no_param(const std::string& /*name*/) { return std::numeric_limits<double>::quiet_NaN(); }

}  // namespace sbtest
