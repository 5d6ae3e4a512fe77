#pragma once
// The shared colour scale of the field panels, without a window (widgets/display_section owns one): each
// dataset's own default scale, and "hold colours" kept per dataset, so a scale held on one dataset is never
// carried into another (a 40 px scale held on one dataset once coloured a 2 px dataset all dark).
#include <map>
#include <string>

namespace sb {

// Below this largest displacement (image px) a frame has no field to scale by: the scale is kept.
inline constexpr double kMinScaledFieldPx = 0.05;
// The automatic arrow gain draws the reference's largest displacement as this fraction of the marker pitch.
inline constexpr double kAutoArrowFractionOfPitch = 0.9;
// The automatic arrow gain's range (the Display section's slider's).
inline constexpr double kMinArrowGain = 0.2;
inline constexpr double kMaxArrowGain = 200.0;

// The largest of 1, 2, 5 x 10^k not above `x` (scale bar lengths). @pre x > 0.
double nice_floor(double x);
// The top of the colour map for a largest displacement: nice_floor(max_px) when it reaches max_px, else twice
// it when that does, else five times it.
// @pre max_px > 0.
double colour_top(double max_px);
// The arrow gain that draws `max_px` as kAutoArrowFractionOfPitch of `marker_pitch_px`, clamped to the range.
// @pre max_px > 0, marker_pitch_px > 0.
double auto_arrow_gain(double max_px, double marker_pitch_px);

struct ScaleSetting {
  double arrow_gain = 4.0;     // drawn arrow length / displacement
  double colour_max_px = 2.0;  // |d| at the top of the colour map
};

// Which colour scale the panels use as datasets open and frames pass.
class ColourScaleKeeper {
 public:
  // A dataset opens (`dataset`: its name, empty for a scene; `sample_max_px`: the sample's largest measured
  // |d|, 0 without a measurement). The colour scale restarts from this dataset's own unless the user held
  // colours for this very dataset, which gets back the scale it held. Another sample of the open dataset
  // keeps a held scale (it can only grow).
  void open(const std::string& dataset, double sample_max_px, double marker_pitch_px);
  // The "hold colours" box, for the open dataset: on, the colour maximum only grows.
  void set_hold(bool hold);
  bool hold() const;
  // The scale for a frame whose reference field's largest |d| is `frame_max_px` (the arrows follow the
  // frame, colours follow it too unless held). A frame without a field keeps the scale.
  ScaleSetting at_frame(double frame_max_px);
  // The open dataset's own default: colours and arrows from its sample's largest |d| (a scene: ScaleSetting{}),
  // and a held scale dropped back to it.
  ScaleSetting reset();
  ScaleSetting current() const { return current_; }

 private:
  ScaleSetting dataset_default() const;

  struct Held {
    bool hold = true;
    double max_px = 0;  // the largest reference |d| seen on this dataset while held
  };
  std::map<std::string, Held> held_;  // by dataset name
  std::string dataset_;
  double sample_max_px_ = 0;
  double marker_pitch_px_ = 33.0;
  ScaleSetting current_;
};

}  // namespace sb
