#pragma once
// Pin tracker for TacTip-type images: bright pins on black, one image against an undeformed reference
// (no time series, so no velocity prediction as in tracker.hpp).
//
// Detection: binary threshold, connected components (OpenCV), kept when the blob looks like one pin
// (area within a band around the reference's median pin area, filled like a disc, not elongated);
// centre = the blob's area centroid.
//
// Correspondence: (1) a global affine map (rest + prior) -> image, fitted robustly (cv::estimateAffine2D,
// RANSAC) to mutual nearest neighbours, repeated with the refined prediction; (2) seeds: the pins that are
// mutual nearest neighbours of a detection within 0.2 pitch of that fit; (3) growth: a pin next to matched
// pins is predicted at rest + prior + the median residual (disp - prior) of its matched first ring and
// takes the nearest free detection inside a gate well under half the pitch (pins with the most matched
// neighbours first, repeated while anything is added); (4) a match whose residual disagrees with its
// neighbours' median by more than a fraction of the pitch is dropped. A pin without an accepted match is
// lost (NaN). The prior (default zero) is what makes a field beyond half a pitch trackable: without it a
// single image is ambiguous on the hexagonal lattice. The tracker alone does not prove its matches right:
// lattice_check.hpp tests them (docs/tracking.md, "TacTip pins").
#include <opencv2/core.hpp>
#include <vector>

#include "core/base/params.hpp"
#include "core/geometry/pose.hpp"

namespace sb {

struct PinTrackerOptions {
  int threshold = 127;             // grey level separating pins from background
  double min_area_factor = 0.3;    // smaller blobs (x reference median area) are noise or masked pins
  double max_area_factor = 2.0;    // larger blobs are merged pins or border junk
  double min_fill = 0.5;           // blob area / bounding-box area (a disc fills 0.785)
  double max_aspect = 2.0;         // bounding-box aspect ratio
  double gate_fraction = 0.4;      // match gate, fraction of the rest pitch
  double outlier_fraction = 0.35;  // max disagreement with the neighbours' median, fraction of the pitch
  int local_iterations = 6;
  bool rim_seeds = false;          // seeds on the rim at rest (else: pins on the global affine fit)
  double rim_width = 2.0;          // pitches: outer band of pins taken as (nearly) fixed seeds
  bool affine_prediction = false;  // local affine field (else the median of the matched neighbours)
};
ParamSet pin_tracker_param_specs();

struct PinDetection {
  Vec2 uv;  // area centroid, pixels (pixel centres at integer coordinates)
  double area_px;
};

// Detects bright pins in a grey (or BGR) image. `reference_area_px` = the median pin area of the
// reference (0: take this image's own median, as for the reference itself).
std::vector<PinDetection> detect_pins(const cv::Mat& image, const PinTrackerOptions& options,
                                      double reference_area_px = 0);

struct PinReference {
  std::vector<Vec2> rest_px;                 // pin index -> rest position, sorted by v then u
  double pitch_px = 0;                       // median nearest-neighbour distance
  double area_px = 0;                        // median pin area
  std::vector<std::vector<int>> neighbours;  // rest-neighbours within 1.6 pitch
  std::vector<char> on_rim;                  // outer pins (within rim_width pitches of the outermost): the seeds
};
// Throws InputError(where) when fewer than 10 pins are found.
PinReference make_pin_reference(const cv::Mat& reference, const PinTrackerOptions& options, const std::string& where);

// Displacement of every reference pin in `image` (NaN where lost). `prior_disp` (empty = zero; one entry
// per reference pin, NaN entries count as zero) is an expected displacement field, e.g. from the sample's
// known inputs (pin_field_prior.hpp): the fit, the seeds and the growth then work on the residual
// disp - prior, so a field of several pitches is tracked as long as the prior is right to within the gate
// (its smooth errors are absorbed by the global fit and the neighbour medians). Throws
// std::invalid_argument when the prior's size is not the reference's.
std::vector<Vec2> track_pins(const PinReference& ref, const std::vector<PinDetection>& detections,
                             const PinTrackerOptions& options, const std::vector<Vec2>& prior_disp = {});
std::vector<Vec2> track_pins(const PinReference& ref, const cv::Mat& image, const PinTrackerOptions& options,
                             const std::vector<Vec2>& prior_disp = {});

}  // namespace sb
