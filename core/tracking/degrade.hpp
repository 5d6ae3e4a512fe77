#pragma once
// Deterministic degradations of a recorded clip, the way real rigs spoil video: optical blur, sensor
// noise, a brightness drift (LED ageing, auto-exposure), lossy JPEG re-encoding, dropped frames and a
// partial occlusion (dirt, a cable, a finger's shadow) sliding over the gel. Each has one strength
// parameter, described once in degrade_param_specs(); the same (kind, strength, seed) on the same frames
// always gives the same pixels, so a study is reproducible.
#include <cstdint>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "core/base/params.hpp"

namespace sb {

enum class DegradeKind { kBlur, kNoise, kBrightness, kJpeg, kDrop, kOcclusion };

struct Degradation {
  DegradeKind kind = DegradeKind::kBlur;
  double strength = 0;  // in the unit of the kind's entry in degrade_param_specs()
  std::uint64_t seed = 1;
};

// One entry per kind (name = the kind's name, unit, default = a moderate strength, range):
//   blur       px            Gaussian sigma
//   noise      grey levels   sigma of additive Gaussian noise, independent per pixel, channel and frame
//   brightness (gain change) gain ramps linearly from 1 at the first frame to 1 + strength at the last
//   jpeg       quality       re-encoded at this JPEG quality (lower = stronger)
//   drop       fraction      of the frames after the rest window that never reach the tracker
//   occlusion  area fraction an opaque disc of this area, the frame's mean colour, crossing the image
//                            left to right along the middle over the clip (outside it at frame 0)
ParamSet degrade_param_specs();

const char* degrade_kind_name(DegradeKind kind);
// "blur:2", "jpeg:20", "drop:0.5". Unknown kinds and out-of-range strengths throw InputError(where).
Degradation parse_degradation(const std::string& text, const std::string& where);
std::string degradation_label(const Degradation& d);  // "blur:2" (shortest round-trip form)

// A degraded clip: the frames the tracker sees and, for each, the index of the source frame.
struct DegradedClip {
  std::vector<cv::Mat> frames;
  std::vector<int> source_frame;
};

// Applies `d` to every frame (8-bit BGR or grey). `protected_frames` leading frames (the tracker's
// rest window) are never dropped; every other kind applies to them too.
DegradedClip degrade_clip(const std::vector<cv::Mat>& frames, const Degradation& d, int protected_frames);

// The per-frame part of the degradations (all but drop, for which it returns the frame unchanged):
// frame `index` of a clip of `frames` frames.
cv::Mat degrade_frame(const cv::Mat& frame, const Degradation& d, int index, int frames);

// The frames kept by a drop of `fraction`: round(fraction * (frames - protected_frames)) of the
// unprotected frames, chosen by `seed`, are removed; the rest stay in order.
std::vector<int> kept_frames(int frames, double fraction, std::uint64_t seed, int protected_frames);

// The occluding disc in frame `index` of `frames` (centre and radius, pixels) for an image W x H.
struct Disc {
  double u, v, radius;
};
Disc occluder(int width, int height, double area_fraction, int index, int frames);

}  // namespace sb
