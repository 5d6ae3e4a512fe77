#include "core/tracking/degrade.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <random>
#include <stdexcept>

#include "core/base/error.hpp"

namespace sb {
namespace {

constexpr DegradeKind kKinds[] = {DegradeKind::kBlur, DegradeKind::kNoise, DegradeKind::kBrightness,
                                  DegradeKind::kJpeg, DegradeKind::kDrop,  DegradeKind::kOcclusion};

// splitmix64: a well-mixed 64-bit stream per (seed, frame), so frame k's noise does not depend on
// how many frames came before it (a dropped or subsampled frame changes nothing else).
std::uint64_t mix(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

cv::Mat add_noise(const cv::Mat& frame, double sigma, std::uint64_t seed, int index) {
  cv::RNG rng(mix(seed ^ mix(static_cast<std::uint64_t>(index))));
  cv::Mat noise(frame.size(), CV_MAKETYPE(CV_32F, frame.channels()));
  rng.fill(noise, cv::RNG::NORMAL, 0.0, sigma);
  cv::Mat f, out;
  frame.convertTo(f, noise.type());
  f += noise;
  f.convertTo(out, frame.type());  // rounds and saturates to 0..255
  return out;
}

cv::Mat reencode_jpeg(const cv::Mat& frame, double quality) {
  std::vector<uchar> bytes;
  cv::imencode(".jpg", frame, bytes, {cv::IMWRITE_JPEG_QUALITY, static_cast<int>(std::lround(quality))});
  return cv::imdecode(bytes, frame.channels() == 1 ? cv::IMREAD_GRAYSCALE : cv::IMREAD_COLOR);
}

cv::Mat occlude(const cv::Mat& frame, double area_fraction, int index, int frames) {
  const Disc d = occluder(frame.cols, frame.rows, area_fraction, index, frames);
  cv::Mat out = frame.clone();
  // The frame's mean colour: an opaque patch that hides the dots without a strong dark edge of its own
  // (a dark patch would be a giant "dot", which the detector already rejects by area).
  const cv::Scalar fill = cv::mean(frame);
  cv::Mat mask = cv::Mat::zeros(frame.size(), CV_8U);
  // Pixel centres strictly inside the disc: the covered area is pi r^2 up to the raster.
  const int y0 = std::max(0, int(std::floor(d.v - d.radius))),
            y1 = std::min(frame.rows - 1, int(std::ceil(d.v + d.radius)));
  const int x0 = std::max(0, int(std::floor(d.u - d.radius))),
            x1 = std::min(frame.cols - 1, int(std::ceil(d.u + d.radius)));
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x <= x1; ++x)
      if ((x - d.u) * (x - d.u) + (y - d.v) * (y - d.v) < d.radius * d.radius) mask.at<uchar>(y, x) = 255;
  out.setTo(fill, mask);
  return out;
}

}  // namespace

ParamSet degrade_param_specs() {
  return ParamSet({
      {"blur", "px", 2.0, 0, 10, "Gaussian blur sigma"},
      {"noise", "grey levels", 10.0, 0, 80, "sigma of additive Gaussian noise per pixel, channel and frame"},
      {"brightness", "", -0.5, -0.9, 2.0, "gain change over the clip: 1 at the first frame, 1 + this at the last"},
      {"jpeg", "quality", 20.0, 1, 100, "JPEG re-encoding quality (lower = stronger)"},
      {"drop", "", 0.5, 0, 0.95, "fraction of the frames after the rest window that are dropped"},
      {"occlusion", "", 0.1, 0, 0.5, "area fraction of an opaque disc crossing the image over the clip"},
  });
}

const char* degrade_kind_name(DegradeKind kind) {
  switch (kind) {
    case DegradeKind::kBlur: return "blur";
    case DegradeKind::kNoise: return "noise";
    case DegradeKind::kBrightness: return "brightness";
    case DegradeKind::kJpeg: return "jpeg";
    case DegradeKind::kDrop: return "drop";
    case DegradeKind::kOcclusion: return "occlusion";
  }
  return "?";
}

Degradation parse_degradation(const std::string& text, const std::string& where) {
  const auto colon = text.find(':');
  const std::string name = text.substr(0, colon);
  const DegradeKind* kind =
      std::find_if(std::begin(kKinds), std::end(kKinds), [&](DegradeKind k) { return name == degrade_kind_name(k); });
  if (colon == std::string::npos || kind == std::end(kKinds))
    throw InputError(where, "'" + text +
                                "' is not KIND:STRENGTH with KIND one of blur, noise, brightness, jpeg, "
                                "drop, occlusion (e.g. blur:2)");
  double strength = 0;
  try {
    std::size_t used = 0;
    strength = std::stod(text.substr(colon + 1), &used);
    if (used != text.size() - colon - 1) throw std::invalid_argument("trailing characters");
  } catch (const std::exception&) {
    throw InputError(where, "'" + text + "': strength '" + text.substr(colon + 1) + "' is not a number");
  }
  ParamSet specs = degrade_param_specs();
  try {
    specs.set(name, strength);  // checks the range
  } catch (const std::invalid_argument&) {
    const ParamSpec& s = specs.specs()[specs.index_of(name)];
    char range[96];
    std::snprintf(range, sizeof range, "[%g, %g]", s.min, s.max);
    throw InputError(where, "'" + text + "': " + name + " strength must be in " + range);
  }
  return {*kind, strength, 1};
}

std::string degradation_label(const Degradation& d) {
  char s[64];
  std::snprintf(s, sizeof s, "%s:%g", degrade_kind_name(d.kind), d.strength);
  return s;
}

Disc occluder(int width, int height, double area_fraction, int index, int frames) {
  const double r = std::sqrt(area_fraction * width * height / M_PI);
  // Centre from u = -r (tangent to the left edge, outside) at the first frame to W + r at the last.
  const double s = frames > 1 ? double(index) / double(frames - 1) : 0.0;
  return {-r + s * (width + 2 * r), 0.5 * (height - 1), r};
}

cv::Mat degrade_frame(const cv::Mat& frame, const Degradation& d, int index, int frames) {
  cv::Mat out;
  switch (d.kind) {
    case DegradeKind::kBlur:
      if (d.strength <= 0) return frame.clone();
      cv::GaussianBlur(frame, out, {0, 0}, d.strength);
      return out;
    case DegradeKind::kNoise: return d.strength > 0 ? add_noise(frame, d.strength, d.seed, index) : frame.clone();
    case DegradeKind::kBrightness: {
      const double gain = 1.0 + d.strength * (frames > 1 ? double(index) / double(frames - 1) : 0.0);
      frame.convertTo(out, -1, gain, 0.0);  // saturates at 255: a brightening drift clips the background
      return out;
    }
    case DegradeKind::kJpeg: return reencode_jpeg(frame, d.strength);
    case DegradeKind::kDrop: return frame.clone();
    case DegradeKind::kOcclusion: return d.strength > 0 ? occlude(frame, d.strength, index, frames) : frame.clone();
  }
  return frame.clone();
}

std::vector<int> kept_frames(int frames, double fraction, std::uint64_t seed, int protected_frames) {
  const int first = std::clamp(protected_frames, 0, frames);
  std::vector<int> candidates(frames - first);
  std::iota(candidates.begin(), candidates.end(), first);
  // A seeded Fisher-Yates with our own mixer (std::shuffle's algorithm is not specified, so its
  // result could differ between standard libraries).
  std::uint64_t state = mix(seed);
  for (int i = static_cast<int>(candidates.size()) - 1; i > 0; --i) {
    state = mix(state);
    std::swap(candidates[i], candidates[state % static_cast<std::uint64_t>(i + 1)]);
  }
  const auto drop = static_cast<std::size_t>(std::lround(fraction * double(candidates.size())));
  std::vector<char> dropped(frames, 0);
  for (std::size_t i = 0; i < drop; ++i) dropped[candidates[i]] = 1;
  std::vector<int> kept;
  for (int f = 0; f < frames; ++f)
    if (!dropped[f]) kept.push_back(f);
  return kept;
}

DegradedClip degrade_clip(const std::vector<cv::Mat>& frames, const Degradation& d, int protected_frames) {
  const int n = static_cast<int>(frames.size());
  DegradedClip clip;
  if (d.kind == DegradeKind::kDrop) {
    clip.source_frame = kept_frames(n, d.strength, d.seed, protected_frames);
  } else {
    clip.source_frame.resize(n);
    std::iota(clip.source_frame.begin(), clip.source_frame.end(), 0);
  }
  for (int f : clip.source_frame) clip.frames.push_back(degrade_frame(frames[f], d, f, n));
  return clip;
}

}  // namespace sb
