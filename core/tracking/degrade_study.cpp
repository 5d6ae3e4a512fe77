#include "core/tracking/degrade_study.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace sb {
namespace {

// clean marker -> degraded marker (-1 none): mutual nearest rest positions within kStudyPairPitch.
std::vector<int> pair_markers(const TrackResult& clean, const TrackResult& degraded) {
  auto nearest = [](const Vec2& p, const std::vector<Vec2>& pts) {
    int best = -1;
    double bd = std::numeric_limits<double>::infinity();
    for (int j = 0; j < static_cast<int>(pts.size()); ++j)
      if ((pts[j] - p).norm() < bd) bd = (pts[j] - p).norm(), best = j;
    return std::pair{best, bd};
  };
  const double gate = kStudyPairPitch * clean.pitch_px;
  std::vector<int> out(clean.rest_px.size(), -1);
  for (int i = 0; i < clean.markers(); ++i) {
    const auto [j, d] = nearest(clean.rest_px[i], degraded.rest_px);
    if (j >= 0 && d < gate && nearest(degraded.rest_px[j], clean.rest_px).first == i) out[i] = j;
  }
  return out;
}

}  // namespace

void DegradeScore::merge(const DegradeScore& o) {
  frames_seen += o.frames_seen;
  marker_frames += o.marker_frames;
  lost += o.lost;
  compared += o.compared;
  jumps += o.jumps;
  onto_neighbour += o.onto_neighbour;
  unverified += o.unverified;
  unpaired_markers += o.unpaired_markers;
  errors_px.insert(errors_px.end(), o.errors_px.begin(), o.errors_px.end());
  for (const auto& e : o.jump_events)
    if (jump_events.size() < kMaxJumpEvents) jump_events.push_back(e);
}

void DegradeScore::finish() {
  rmse_px = p95_px = max_px = 0;
  if (errors_px.empty()) return;
  std::vector<double> e = errors_px;
  double ss = 0;
  for (double x : e) ss += x * x;
  rmse_px = std::sqrt(ss / double(e.size()));
  std::sort(e.begin(), e.end());
  p95_px = e[std::min(e.size() - 1, static_cast<std::size_t>(std::ceil(0.95 * double(e.size()))) - 1)];
  max_px = e.back();
}

DegradeScore compare_to_clean(const TrackResult& clean, const TrackResult& degraded,
                              const std::vector<int>& source_frame) {
  DegradeScore s;
  const std::vector<int> pair = pair_markers(clean, degraded);
  const double jump_px = kJumpPitch * clean.pitch_px;
  for (int j : pair) s.unpaired_markers += j < 0 ? 1 : 0;
  const int frames = std::min(degraded.frames(), static_cast<int>(source_frame.size()));
  s.frames_seen = frames;
  std::vector<Vec2> clean_uv(clean.markers());
  for (int k = 0; k < frames; ++k) {
    const int f = source_frame[k];
    if (f < 0 || f >= clean.frames()) continue;
    for (int i = 0; i < clean.markers(); ++i) clean_uv[i] = clean.rest_px[i] + clean.disp_px[f][i];
    for (int i = 0; i < clean.markers(); ++i) {
      const int j = pair[i];
      const Vec2 uv = j >= 0 ? Vec2(degraded.rest_px[j] + degraded.disp_px[k][j]) : Vec2(NAN, NAN);
      const bool clean_ok = clean_uv[i].allFinite();
      if (clean_ok) {
        ++s.marker_frames;
        if (!uv.allFinite()) ++s.lost;
      }
      if (!uv.allFinite()) continue;
      // On another marker's dot: the nearest clean position is a different marker's, within jump_px.
      int other = -1;
      double od = jump_px;
      for (int m = 0; m < clean.markers(); ++m)
        if (clean_uv[m].allFinite() && (clean_uv[m] - uv).norm() < od) od = (clean_uv[m] - uv).norm(), other = m;
      const bool onto = other >= 0 && other != i;
      auto record_jump = [&] {
        ++s.jumps;
        s.onto_neighbour += onto ? 1 : 0;
        if (s.jump_events.size() < DegradeScore::kMaxJumpEvents)
          s.jump_events.push_back({f, i, clean_uv[i], uv, onto ? other : -1});
      };
      if (!clean_ok) {
        if (onto)
          record_jump();
        else
          ++s.unverified;
        continue;
      }
      const double e = (uv - clean_uv[i]).norm();
      ++s.compared;
      s.errors_px.push_back(e);
      if (onto || e > jump_px) record_jump();
    }
  }
  s.finish();
  return s;
}

DegradeStudy run_degrade_study(const std::vector<cv::Mat>& frames, const std::vector<Degradation>& degradations,
                               const TrackerOptions& options, const Progress& progress) {
  DegradeStudy study;
  study.clean = track_frames(frames, options);
  for (std::size_t d = 0; d < degradations.size(); ++d) {
    progress.check("degradation study");
    progress("degradation study", double(d) / double(degradations.size()));
    const DegradedClip clip = degrade_clip(frames, degradations[d], options.rest_frames);
    DegradeScore s = compare_to_clean(study.clean, track_frames(clip.frames, options), clip.source_frame);
    s.label = degradation_label(degradations[d]);
    study.scores.push_back(std::move(s));
  }
  return study;
}

}  // namespace sb
