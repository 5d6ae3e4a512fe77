#include "core/workbench/colour_scale.hpp"

#include <algorithm>
#include <cmath>

namespace sb {

double nice_floor(double x) {
  const double p = std::pow(10.0, std::floor(std::log10(x)));
  for (double m : {5.0, 2.0, 1.0})
    if (m * p <= x) return m * p;
  return p;
}

double colour_top(double max_px) {
  const double top = nice_floor(max_px);
  return top >= max_px ? top : (top * 2 >= max_px ? top * 2 : top * 5);
}

double auto_arrow_gain(double max_px, double marker_pitch_px) {
  return std::clamp(kAutoArrowFractionOfPitch * marker_pitch_px / max_px, kMinArrowGain, kMaxArrowGain);
}

void ColourScaleKeeper::open(const std::string& dataset, double sample_max_px, double marker_pitch_px) {
  dataset_ = dataset;
  sample_max_px_ = sample_max_px;
  marker_pitch_px_ = marker_pitch_px;
  Held& h = held_[dataset_];
  if (!h.hold) h.max_px = 0;  // not held for this dataset: its own scale
  current_ = dataset_default();
  if (h.hold) h.max_px = std::max(h.max_px, sample_max_px_);
  if (h.hold && h.max_px >= kMinScaledFieldPx) current_.colour_max_px = colour_top(h.max_px);
}

void ColourScaleKeeper::set_hold(bool hold) {
  Held& h = held_[dataset_];
  h.hold = hold;
  h.max_px = 0;  // a hold starts again from the dataset's own largest measurement
}

bool ColourScaleKeeper::hold() const {
  const auto it = held_.find(dataset_);
  return it == held_.end() || it->second.hold;
}

ScaleSetting ColourScaleKeeper::at_frame(double frame_max_px) {
  if (!(frame_max_px >= kMinScaledFieldPx)) return current_;
  current_.arrow_gain = auto_arrow_gain(frame_max_px, marker_pitch_px_);
  double colour_px = frame_max_px;
  Held& h = held_[dataset_];
  if (h.hold) {
    h.max_px = std::max({h.max_px, frame_max_px, sample_max_px_});
    colour_px = h.max_px;
  }
  current_.colour_max_px = colour_top(colour_px);
  return current_;
}

ScaleSetting ColourScaleKeeper::reset() {
  held_[dataset_].max_px = 0;
  current_ = dataset_default();
  return current_;
}

ScaleSetting ColourScaleKeeper::dataset_default() const {
  if (!(sample_max_px_ >= kMinScaledFieldPx)) return ScaleSetting{};
  return {auto_arrow_gain(sample_max_px_, marker_pitch_px_), colour_top(sample_max_px_)};
}

}  // namespace sb
