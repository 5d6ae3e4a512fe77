#include "core/tracking/tracker.hpp"
#include "core/base/median.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <numeric>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>
#include <regex>

#include "core/base/error.hpp"
#include "core/base/numbers.hpp"

namespace fs = std::filesystem;

namespace sb {
namespace {

const Vec2 kLost{kNaN, kNaN};

// Red drawing (the vendor's arrows and crosses): a saturated red that no gel shading produces.
constexpr int kOverlayMinRed = 120;
constexpr int kOverlayMinRedExcess = 70;
constexpr int kOverlayMinPixels = 10;  // fewer red pixels: no overlay, skip the fill
// Overlay fill: box widths tried in turn (pixels), and the least valid weight that may fill a pixel.
constexpr int kFillBoxesPx[] = {5, 9, 17};
constexpr float kFillMinWeight = 0.05f;
// Rest-neighbours within this many pitches feed the smooth-field prior (the 8-neighbourhood is at 1.41).
constexpr double kNeighbourRadiusPitch = 1.6;
// A match farther than this (pitches) from its neighbours' median displacement is re-predicted.
constexpr double kFieldDisagreementPitch = 0.35;
// A match must be unambiguous: its distance from the prediction at most this fraction of the distance to
// the next detection. On a lattice, a prediction off by e along a row has its own dot at e and the
// neighbour's at pitch - e: the ratio 0.5 accepts e < pitch / 3 and leaves the marker lost beyond, where
// the prediction no longer tells the two dots apart (dropped frames, a sudden fast motion).
constexpr double kAmbiguityRatio = 0.5;
// After the second match, a marker farther than this (pitches) from its neighbours' median displacement
// is lost rather than kept: a neighbour's dot is a pitch away, real strain between neighbours stays well
// under this (the 30 px ramp test puts neighbours up to 0.6 pitch out of step over 1.41 pitches).
constexpr double kFinalDisagreementPitch = 0.75;
// ... and only when at least this many neighbours were tracked (fewer: no reliable field to compare with).
constexpr int kFinalMinNeighbours = 3;
// Lattice slips: markers adjacent at rest (closer than kAdjacentPitch: the 4-neighbours of a square grid,
// the 6 of a hexagonal one) whose displacements differ by more than kSlipPitch cannot both be right: the
// gel would be stretched or compressed by more than 60 % between them, while a block of markers that took
// their neighbours' dots differs from the markers around it by about one pitch. Of two groups that
// contradict each other this way the smaller one is lost (see drop_contradicted_groups).
constexpr double kAdjacentPitch = 1.2;
constexpr double kSlipPitch = 0.6;
// A first-pass match within this (pitches) of its prediction, agreeing with its neighbours, seeds the
// second pass; the second pass grows from the seeds at most kGrowthPasses rings.
constexpr double kSeedPitch = 0.2;
constexpr int kGrowthPasses = 8;
// Fewer confident matches than this in a frame: the prediction failed everywhere; grow from all matches
// that agree with their neighbours instead (the tracker's behaviour before the growth pass).
constexpr int kMinSeeds = 3;
// Lost markers are predicted from tracked neighbours up to this many rings away (then from rest).
constexpr int kPredictionRings = 4;
// Rest frames: a detection within this (pitches) of a frame-0 marker is the same marker.
constexpr double kRestMatchPitch = 0.3;
// Rows at rest are split where consecutive sorted v differ by more than this (pitches).
constexpr double kRowGapPitch = 0.5;

// Brightness = per-pixel max over the colour channels; red overlay pixels filled from their surroundings.
cv::Mat brightness(const cv::Mat& frame, const TrackerOptions& options) {
  if (frame.channels() == 1) return frame;
  std::vector<cv::Mat> ch;
  cv::split(frame, ch);
  cv::Mat bright;
  cv::max(ch[0], ch[1], bright);
  cv::max(bright, ch[2], bright);
  if (!options.remove_overlay) return bright;
  cv::Mat other, excess, red;
  cv::max(ch[0], ch[1], other);
  cv::subtract(ch[2], other, excess);
  cv::Mat mask = (excess > kOverlayMinRedExcess) & (ch[2] > kOverlayMinRed);
  if (cv::countNonZero(mask) < kOverlayMinPixels) return bright;
  // The video codec smears the drawing by a pixel: grow the mask, then fill it from the valid pixels
  // around it (normalised convolution: cheap, and a line across a dot is filled with the dot's darkness).
  cv::dilate(mask, mask, cv::Mat(), cv::Point(-1, -1), 1);
  cv::Mat valid, value;
  cv::bitwise_not(mask, valid);
  valid.convertTo(valid, CV_32F, 1.0 / 255.0);
  bright.convertTo(value, CV_32F);
  cv::Mat filled = value.clone();
  for (int box : kFillBoxesPx) {
    cv::Mat num, den;
    cv::blur(value.mul(valid), num, {box, box});
    cv::blur(valid, den, {box, box});
    for (int y = 0; y < filled.rows; ++y) {
      const uchar* m = mask.ptr<uchar>(y);
      const float* n = num.ptr<float>(y);
      const float* d = den.ptr<float>(y);
      float* out = filled.ptr<float>(y);
      float* v = value.ptr<float>(y);
      float* ok = valid.ptr<float>(y);
      for (int x = 0; x < filled.cols; ++x)
        if (m[x] && ok[x] == 0.f && d[x] > kFillMinWeight) out[x] = v[x] = n[x] / d[x], ok[x] = 1.f;
    }
  }
  cv::Mat repaired;
  filled.convertTo(repaired, CV_8U);
  return repaired;
}

// Relative darkness: (background - image) / background, background = closing (dots removed).
cv::Mat relative_darkness(const cv::Mat& bright, const TrackerOptions& options) {
  int k = static_cast<int>(std::lround(1.3 * options.max_dot_diameter_px)) | 1;
  cv::Mat background;
  cv::morphologyEx(bright, background, cv::MORPH_CLOSE, cv::getStructuringElement(cv::MORPH_RECT, {k, k}));
  cv::blur(background, background, {k, k});
  cv::Mat bf, bgf;
  bright.convertTo(bf, CV_32F);
  background.convertTo(bgf, CV_32F);
  cv::max(bgf, 1.0, bgf);
  cv::Mat dark = (bgf - bf) / bgf;
  cv::max(dark, 0.0, dark);
  // A light blur: pixel noise out of the threshold, symmetric so the centroid is not biased.
  cv::GaussianBlur(dark, dark, {3, 3}, 0.8);
  return dark;
}

}  // namespace

ParamSet tracker_param_specs() {
  const TrackerOptions d;
  return ParamSet({
      {"rest_frames", "frames", double(d.rest_frames), 1, 50, "rest = per-marker median over the first frames"},
      {"max_dot_diameter_px", "px", d.max_dot_diameter_px, 4, 80, "largest dot; sets the top-hat box"},
      {"min_contrast", "", d.min_contrast, 0.01, 0.9, "lowest relative darkness of a dot"},
      {"min_area_px", "px^2", d.min_area_px, 1, 1000, "smaller blobs are noise"},
      {"max_area_factor", "", d.max_area_factor, 1.1, 10, "larger blobs (x median area) are merged dots"},
      {"min_border_area_factor", "", d.min_border_area_factor, 0, 1, "area a border-cut dot must keep"},
      {"gate_fraction", "", d.gate_fraction, 0.1, 0.5, "match gate as a fraction of the marker pitch"},
      {"velocity_gain", "", d.velocity_gain, 0, 1.5, "weight of the last velocity in the prediction"},
  });
}

void parse_grid(const std::string& text, const std::string& where, TrackerOptions& options) {
  if (text == "auto") {
    options.grid_rows = options.grid_cols = 0;
    return;
  }
  static const std::regex kGrid(R"((\d{1,3})x(\d{1,3}))");
  std::smatch m;
  if (!std::regex_match(text, m, kGrid) || std::stoi(m[1]) < 2 || std::stoi(m[2]) < 2)
    throw InputError(where, "grid '" + text + "' is not ROWSxCOLS (e.g. 7x9, 8x10, 11x9) or auto");
  options.grid_rows = std::stoi(m[1]);
  options.grid_cols = std::stoi(m[2]);
}

std::vector<MarkerDetection> detect_markers(const cv::Mat& frame, const TrackerOptions& options) {
  if (frame.empty()) return {};
  cv::Mat bgr = frame;
  if (frame.depth() != CV_8U) frame.convertTo(bgr, CV_8U);
  if (bgr.channels() == 4) cv::cvtColor(bgr, bgr, cv::COLOR_BGRA2BGR);
  const cv::Mat dark = relative_darkness(brightness(bgr, options), options);

  cv::Mat dark8;
  dark.convertTo(dark8, CV_8U, 255.0);
  cv::Mat binary;
  const double otsu = cv::threshold(dark8, binary, 0, 255, cv::THRESH_BINARY | cv::THRESH_OTSU) / 255.0;
  const double thr = std::max(otsu, options.min_contrast);
  binary = dark > thr;

  cv::Mat labels, stats, centroids;
  const int n = cv::connectedComponentsWithStats(binary, labels, stats, centroids, 8, CV_32S);
  std::vector<double> areas;
  for (int c = 1; c < n; ++c)
    if (stats.at<int>(c, cv::CC_STAT_AREA) >= options.min_area_px) areas.push_back(stats.at<int>(c, cv::CC_STAT_AREA));
  const double typical_area = median(areas);
  const int W = dark.cols, H = dark.rows;
  // Centroid weights start at half the threshold so the blurred rim counts symmetrically.
  const float w0 = static_cast<float>(0.5 * thr);

  std::vector<MarkerDetection> out;
  for (int c = 1; c < n; ++c) {
    const int area = stats.at<int>(c, cv::CC_STAT_AREA);
    if (area < options.min_area_px || area > options.max_area_factor * typical_area) continue;
    const int x0 = stats.at<int>(c, cv::CC_STAT_LEFT), y0 = stats.at<int>(c, cv::CC_STAT_TOP);
    const int w = stats.at<int>(c, cv::CC_STAT_WIDTH), h = stats.at<int>(c, cv::CC_STAT_HEIGHT);
    const bool border = x0 == 0 || y0 == 0 || x0 + w == W || y0 + h == H;
    if (border && area < options.min_border_area_factor * typical_area) continue;
    double sw = 0, su = 0, sv = 0;
    for (int y = std::max(0, y0 - 1); y < std::min(H, y0 + h + 1); ++y) {
      const int* lab = labels.ptr<int>(y);
      const float* d = dark.ptr<float>(y);
      for (int x = std::max(0, x0 - 1); x < std::min(W, x0 + w + 1); ++x) {
        if (lab[x] != c && lab[x] != 0) continue;
        const double wt = d[x] - w0;
        if (wt <= 0) continue;
        sw += wt;
        su += wt * x;
        sv += wt * y;
      }
    }
    if (sw <= 0) continue;
    out.push_back({Vec2(su / sw, sv / sw), double(area), border});
  }
  return out;
}

double TrackResult::lost_fraction() const {
  std::size_t lost = 0, all = 0;
  for (const auto& f : disp_px)
    for (const auto& d : f) {
      ++all;
      lost += d.allFinite() ? 0 : 1;
    }
  return all ? double(lost) / double(all) : 0.0;
}

MarkerTracker::MarkerTracker(TrackerOptions options) : options_(options) {}

void MarkerTracker::add_frame(const cv::Mat& frame) {
  if (result_.image_width == 0) {
    result_.image_width = frame.cols;
    result_.image_height = frame.rows;
  }
  auto detections = detect_markers(frame, options_);
  if (!initialised_) {
    pending_.push_back(std::move(detections));
    if (static_cast<int>(pending_.size()) >= std::max(1, options_.rest_frames)) initialise_rest();
    return;
  }
  std::vector<Vec2> disp;
  track(detections, disp);
  result_.disp_px.push_back(std::move(disp));
}

TrackResult MarkerTracker::result() {
  if (!initialised_ && !pending_.empty()) initialise_rest();
  return result_;
}

namespace {

double nearest_neighbour_pitch(const std::vector<Vec2>& pts) {
  std::vector<double> nn;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t j = 0; j < pts.size(); ++j)
      if (i != j) best = std::min(best, (pts[i] - pts[j]).norm());
    if (std::isfinite(best)) nn.push_back(best);
  }
  return median(nn);
}

// Greedy one-to-one assignment: all unambiguous marker/detection pairs inside the gate, shortest first; a
// marker or a detection is used once. A pair is unambiguous when the detection is the marker's nearest and
// the second nearest is farther by 1 / kAmbiguityRatio. Returns the detection index per marker (-1 none).
std::vector<int> assign(const std::vector<Vec2>& predicted_uv, const std::vector<MarkerDetection>& det, double gate) {
  struct Pair {
    double d2;
    int marker, detection;
  };
  std::vector<Pair> pairs;
  const double gate2 = gate * gate;
  constexpr double kRatio2 = kAmbiguityRatio * kAmbiguityRatio;
  for (int i = 0; i < static_cast<int>(predicted_uv.size()); ++i) {
    if (!predicted_uv[i].allFinite()) continue;
    double best = std::numeric_limits<double>::infinity(), second = best;
    int best_j = -1;
    for (int j = 0; j < static_cast<int>(det.size()); ++j) {
      const double d2 = (predicted_uv[i] - det[j].uv).squaredNorm();
      if (d2 < best)
        second = best, best = d2, best_j = j;
      else if (d2 < second)
        second = d2;
    }
    if (best_j >= 0 && best < gate2 && best <= kRatio2 * second) pairs.push_back({best, i, best_j});
  }
  std::sort(pairs.begin(), pairs.end(), [](const Pair& a, const Pair& b) { return a.d2 < b.d2; });
  std::vector<int> of_marker(predicted_uv.size(), -1);
  std::vector<char> used(det.size(), 0);
  for (const auto& p : pairs) {
    if (of_marker[p.marker] >= 0 || used[p.detection]) continue;
    of_marker[p.marker] = p.detection;
    used[p.detection] = 1;
  }
  return of_marker;
}

// Groups of tracked markers connected through adjacent pairs whose displacements agree (within kSlipPitch);
// largest group first, a group that contradicts (an adjacent pair that disagrees) a kept larger group is
// set lost. A single marker on a neighbour's dot is a group of one contradicted by all around it; a block
// that slipped by a pitch (dropped frames, a sudden motion) is contradicted along its boundary by the
// markers that did not. Groups isolated by lost markers contradict nothing and are kept.
void drop_contradicted_groups(const std::vector<std::vector<int>>& adjacent, double pitch, std::vector<Vec2>& disp) {
  const int n = static_cast<int>(disp.size());
  const double slip = kSlipPitch * pitch;
  auto agree = [&](int i, int j) { return (disp[i] - disp[j]).norm() <= slip; };
  std::vector<int> group(n, -1);
  std::vector<std::vector<int>> members;
  for (int s = 0; s < n; ++s) {
    if (group[s] >= 0 || !disp[s].allFinite()) continue;
    const int g = static_cast<int>(members.size());
    members.push_back({s});
    group[s] = g;
    for (std::size_t k = 0; k < members[g].size(); ++k) {
      const int i = members[g][k];
      for (int j : adjacent[i])
        if (group[j] < 0 && disp[j].allFinite() && agree(i, j)) group[j] = g, members[g].push_back(j);
    }
  }
  std::vector<int> order(members.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return members[a].size() > members[b].size(); });
  std::vector<char> kept(members.size(), 0);
  for (int g : order) {
    bool contradicted = false;
    for (int i : members[g])
      for (int j : adjacent[i])
        contradicted = contradicted || (group[j] >= 0 && group[j] != g && kept[group[j]] &&
                                        members[group[j]].size() > members[g].size() && !agree(i, j));
    kept[g] = !contradicted;
    if (contradicted)
      for (int i : members[g]) disp[i] = kLost;
  }
}

}  // namespace

void MarkerTracker::initialise_rest() {
  initialised_ = true;
  const auto& first = pending_.front();
  std::vector<Vec2> pts;
  for (const auto& d : first) pts.push_back(d.uv);
  result_.pitch_px = nearest_neighbour_pitch(pts);
  const double pitch = std::isfinite(result_.pitch_px) ? result_.pitch_px : 1.0;

  // Per-marker median over the rest frames (markers are frame-0 detections).
  std::vector<Vec2> rest;
  for (const Vec2& p : pts) {
    std::vector<double> us{p.x()}, vs{p.y()};
    for (std::size_t f = 1; f < pending_.size(); ++f) {
      const MarkerDetection* best = nullptr;
      double bd = kRestMatchPitch * pitch;
      for (const auto& d : pending_[f])
        if ((d.uv - p).norm() < bd) bd = (d.uv - p).norm(), best = &d;
      if (best) us.push_back(best->uv.x()), vs.push_back(best->uv.y());
    }
    rest.emplace_back(median(us), median(vs));
  }

  // Row-major order: rows are clusters of v, each row sorted by u.
  std::sort(rest.begin(), rest.end(), [](const Vec2& a, const Vec2& b) { return a.y() < b.y(); });
  std::vector<std::vector<Vec2>> rows;
  for (std::size_t i = 0; i < rest.size(); ++i) {
    if (i == 0 || rest[i].y() - rest[i - 1].y() > kRowGapPitch * pitch) rows.emplace_back();
    rows.back().push_back(rest[i]);
  }
  result_.rest_px.clear();
  bool regular = !rows.empty();
  for (auto& row : rows) {
    std::sort(row.begin(), row.end(), [](const Vec2& a, const Vec2& b) { return a.x() < b.x(); });
    regular = regular && row.size() == rows.front().size();
    result_.rest_px.insert(result_.rest_px.end(), row.begin(), row.end());
  }
  result_.grid_rows = regular ? static_cast<int>(rows.size()) : 0;
  result_.grid_cols = regular ? static_cast<int>(rows.front().size()) : 0;
  if (!regular)
    result_.warnings.push_back("rest markers do not form a regular grid (" + std::to_string(rows.size()) +
                               " rows of unequal length); markers are indexed row-major anyway");
  if (options_.grid_rows > 0) {
    const bool match = (result_.grid_rows == options_.grid_rows && result_.grid_cols == options_.grid_cols) ||
                       (result_.grid_rows == options_.grid_cols && result_.grid_cols == options_.grid_rows);
    if (!match)
      result_.warnings.push_back("expected grid " + std::to_string(options_.grid_rows) + "x" +
                                 std::to_string(options_.grid_cols) + ", found " + std::to_string(rows.size()) +
                                 " rows, " + std::to_string(result_.rest_px.size()) + " markers");
  }

  const int n = result_.markers();
  neighbours_.assign(n, {});
  adjacent_.assign(n, {});
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const double d = (result_.rest_px[i] - result_.rest_px[j]).norm();
      if (i != j && d < kNeighbourRadiusPitch * pitch) neighbours_[i].push_back(j);
      if (i != j && d < kAdjacentPitch * pitch) adjacent_[i].push_back(j);
    }
  velocity_.assign(n, Vec2::Zero());
  last_seen_.assign(n, -1);

  auto pending = std::move(pending_);
  pending_.clear();
  for (const auto& det : pending) {
    std::vector<Vec2> disp;
    track(det, disp);
    result_.disp_px.push_back(std::move(disp));
  }
}

std::vector<Vec2> MarkerTracker::neighbour_median(const std::vector<Vec2>& disp, std::size_t min_count) const {
  std::vector<Vec2> out(disp.size(), kLost);
  for (std::size_t i = 0; i < disp.size(); ++i) {
    std::vector<double> us, vs;
    for (int j : neighbours_[i])
      if (disp[j].allFinite()) us.push_back(disp[j].x()), vs.push_back(disp[j].y());
    if (us.size() >= min_count) out[i] = Vec2(median(us), median(vs));
  }
  return out;
}

std::vector<Vec2> MarkerTracker::match(const std::vector<Vec2>& predicted,
                                       const std::vector<MarkerDetection>& det) const {
  const int n = result_.markers();
  std::vector<Vec2> uv(n);
  for (int i = 0; i < n; ++i) uv[i] = result_.rest_px[i] + predicted[i];
  const std::vector<int> a = assign(uv, det, options_.gate_fraction * result_.pitch_px);
  std::vector<Vec2> d(n, kLost);
  for (int i = 0; i < n; ++i)
    if (a[i] >= 0) d[i] = det[a[i]].uv - result_.rest_px[i];
  return d;
}

std::vector<Vec2> MarkerTracker::predict(const std::vector<Vec2>& previous) const {
  const int n = result_.markers();
  // Own motion for markers seen in the last frame, neighbours' motion for the others.
  std::vector<Vec2> pred(n, kLost);
  for (int i = 0; i < n; ++i)
    if (previous[i].allFinite()) pred[i] = previous[i] + options_.velocity_gain * velocity_[i];
  // Inward, ring by ring: a marker lost among lost markers (under an occluder, inside a block that was
  // dropped) takes its prediction from the nearest tracked ones rather than from its rest position.
  for (int ring = 0; ring < kPredictionRings; ++ring) {
    const std::vector<Vec2> from_neighbours = neighbour_median(pred);
    bool filled = false;
    for (int i = 0; i < n; ++i)
      if (!pred[i].allFinite() && from_neighbours[i].allFinite()) pred[i] = from_neighbours[i], filled = true;
    if (!filled) break;
  }
  for (int i = 0; i < n; ++i)
    if (!pred[i].allFinite()) pred[i] = Vec2::Zero();
  return pred;
}

// Prediction 2 (smooth-field prior), grown from the confident matches: a match is confident when it lies
// close to its prediction and agrees with its neighbours. Markers around confident ones are re-predicted
// from their median displacement and matched again, ring by ring, so a region whose prediction failed
// (a step larger than the gate after dropped frames) is reached from where it did not, instead of
// keeping the nearest dot, which may be a neighbour's. Markers never reached stay lost for the frame.
std::vector<Vec2> MarkerTracker::grow(const std::vector<Vec2>& first, const std::vector<Vec2>& pred,
                                      const std::vector<MarkerDetection>& det) const {
  const int n = result_.markers();
  const double pitch = result_.pitch_px;
  const std::vector<Vec2> field = neighbour_median(first);
  std::vector<Vec2> agreeing(n, kLost), accepted(n, kLost);
  int seeds = 0;
  for (int i = 0; i < n; ++i) {
    if (!first[i].allFinite() ||
        (field[i].allFinite() && (first[i] - field[i]).norm() >= kFieldDisagreementPitch * pitch))
      continue;
    agreeing[i] = first[i];
    if ((first[i] - pred[i]).norm() < kSeedPitch * pitch) accepted[i] = first[i], ++seeds;
  }
  // No confident match anywhere (the whole gel moved unpredictably): the agreeing matches seed instead.
  if (seeds < kMinSeeds) accepted = agreeing;
  for (int pass = 0; pass < kGrowthPasses; ++pass) {
    // Predicted from two or more accepted neighbours where there are; from a single one (sparse seeds,
    // e.g. only the corners moved little) only with the tighter seed tolerance.
    const std::vector<Vec2> around2 = neighbour_median(accepted, 2), around1 = neighbour_median(accepted, 1);
    std::vector<Vec2> around(n), pred2(n);
    for (int i = 0; i < n; ++i) {
      around[i] = around2[i].allFinite() ? around2[i] : around1[i];
      pred2[i] = accepted[i].allFinite() ? accepted[i] : around[i].allFinite() ? around[i] : pred[i];
    }
    const std::vector<Vec2> again = match(pred2, det);
    bool grown = false;
    for (int i = 0; i < n; ++i) {
      if (accepted[i].allFinite() && !again[i].allFinite()) accepted[i] = kLost;  // its dot went to a better claim
      if (accepted[i].allFinite() || !around[i].allFinite() || !again[i].allFinite()) continue;
      const double tolerance = (around2[i].allFinite() ? kFieldDisagreementPitch : kSeedPitch) * pitch;
      if ((again[i] - around[i]).norm() < tolerance) accepted[i] = again[i], grown = true;
    }
    if (!grown) break;
  }
  return accepted;
}

// Last: a match still far from its neighbours' field is more likely a neighbour's dot than strain; a group
// that slipped as a whole is caught where it borders the markers that did not.
void MarkerTracker::drop_contradicted(std::vector<Vec2>& disp) const {
  const std::vector<Vec2> field = neighbour_median(disp);
  for (int i = 0; i < result_.markers(); ++i) {
    if (!disp[i].allFinite() || !field[i].allFinite()) continue;
    int tracked = 0;
    for (int j : neighbours_[i]) tracked += disp[j].allFinite() ? 1 : 0;
    if (tracked >= kFinalMinNeighbours && (disp[i] - field[i]).norm() > kFinalDisagreementPitch * result_.pitch_px)
      disp[i] = kLost;
  }
  drop_contradicted_groups(adjacent_, result_.pitch_px, disp);
}

void MarkerTracker::track(const std::vector<MarkerDetection>& det, std::vector<Vec2>& disp_out) {
  const int n = result_.markers();
  const int t = result_.frames();
  const std::vector<Vec2> previous = t > 0 ? result_.disp_px.back() : std::vector<Vec2>(n, Vec2::Zero());
  const std::vector<Vec2> pred = predict(previous);
  disp_out = grow(match(pred, det), pred, det);
  drop_contradicted(disp_out);

  for (int i = 0; i < n; ++i) {
    const bool seen_now = disp_out[i].allFinite();
    velocity_[i] = seen_now && previous[i].allFinite() && last_seen_[i] == t - 1 ? Vec2(disp_out[i] - previous[i])
                                                                                 : Vec2(Vec2::Zero());
    if (seen_now) last_seen_[i] = t;
  }
}

TrackResult track_frames(const std::vector<cv::Mat>& frames, const TrackerOptions& options) {
  MarkerTracker tracker(options);
  for (const auto& f : frames) tracker.add_frame(f);
  return tracker.result();
}

std::vector<cv::Mat> read_video_frames(const std::string& path) {
  if (!fs::is_regular_file(path)) throw InputError(path, "video not found");
  cv::VideoCapture cap(path, cv::CAP_FFMPEG);  // FFmpeg only: no GStreamer or image-sequence guesses
  if (!cap.isOpened()) throw InputError(path, "cannot open video (not a video or unsupported codec)");
  std::vector<cv::Mat> frames;
  cv::Mat f;
  while (cap.read(f)) frames.push_back(f.clone());
  if (frames.empty()) throw InputError(path, "video has no readable frame");
  return frames;
}

TrackResult track_video(const std::string& path, const TrackerOptions& options, const Progress& progress) {
  if (!fs::is_regular_file(path)) throw InputError(path, "video not found");
  cv::VideoCapture cap(path, cv::CAP_FFMPEG);  // FFmpeg only: no GStreamer or image-sequence guesses
  if (!cap.isOpened()) throw InputError(path, "cannot open video (not a video or unsupported codec)");
  MarkerTracker tracker(options);
  const double total = cap.get(cv::CAP_PROP_FRAME_COUNT);  // an estimate for some containers; 0 when unknown
  cv::Mat f;
  int count = 0;
  while (cap.read(f)) {
    progress.check(path);
    tracker.add_frame(f);
    ++count;
    if (count % 50 == 0) progress("tracking " + path, total > 0 ? std::min(1.0, count / total) : -1.0);
  }
  if (count == 0) throw InputError(path, "video has no readable frame");
  return tracker.result();
}

TrackResult track_frames_dir(const std::string& frames_dir, const TrackerOptions& options, const Progress& progress) {
  if (!fs::is_directory(frames_dir)) throw InputError(frames_dir, "frames directory not found");
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(frames_dir)) {
    std::string ext = e.path().extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), ::tolower);
    if (e.is_regular_file() && (ext == ".png" || ext == ".jpg" || ext == ".jpeg" || ext == ".bmp"))
      files.push_back(e.path());
  }
  std::sort(files.begin(), files.end());
  if (files.empty()) throw InputError(frames_dir, "no image files (png/jpg/bmp) in frames directory");
  MarkerTracker tracker(options);
  for (std::size_t i = 0; i < files.size(); ++i) {
    const fs::path& p = files[i];
    progress.check(frames_dir);
    if (i % 50 == 0) progress("tracking " + frames_dir, static_cast<double>(i) / static_cast<double>(files.size()));
    cv::Mat img = cv::imread(p.string(), cv::IMREAD_COLOR);
    if (img.empty()) throw InputError(p.string(), "cannot read image");
    tracker.add_frame(img);
  }
  return tracker.result();
}

}  // namespace sb
