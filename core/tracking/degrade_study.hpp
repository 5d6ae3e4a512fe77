#pragma once
// How the tracker holds up under a degradation: the clip is tracked clean, then degraded (degrade.hpp),
// and the degraded track is scored against the clean one, which is the reference (on real video there is
// no other). A marker may be lost (NaN) under degradation, which costs coverage; it must never be given
// a wrong dot, which costs correctness: those are counted as jumps.
#include <string>
#include <vector>

#include "core/base/progress.hpp"
#include "core/tracking/degrade.hpp"
#include "core/tracking/tracker.hpp"

namespace sb {

// Degraded markers are paired with clean ones by nearest rest position, mutual, within this many pitches.
constexpr double kStudyPairPitch = 0.3;
// A tracked position farther than this (pitches) from the clean one is a jump; so is one nearer to a
// different marker's clean position than this.
constexpr double kJumpPitch = 0.5;

// Where a jump happened (for inspection: `track --draw` on the degraded clip shows it).
struct JumpEvent {
  int source_frame = 0;
  int marker = 0;  // clean marker index
  Vec2 clean_uv;   // NaN when the clean track lost the marker there
  Vec2 degraded_uv;
  int onto_marker = -1;  // the other marker whose clean position it landed on, -1 none
};

struct DegradeScore {
  std::string label;         // "blur:2"
  long frames_seen = 0;      // frames the degraded tracker saw
  long marker_frames = 0;    // clean-tracked (finite) marker-frames in those frames
  long lost = 0;             // of these, NaN in the degraded track (unpaired markers count as lost)
  long compared = 0;         // finite in both
  long jumps = 0;            // finite degraded positions off the clean track by > kJumpPitch, or on another's dot
  long onto_neighbour = 0;   // of the jumps: nearest to a different marker's clean position, within kJumpPitch
  long unverified = 0;       // finite degraded positions where the clean track is NaN (not scored)
  int unpaired_markers = 0;  // clean markers without a degraded marker at rest
  double rmse_px = 0, p95_px = 0, max_px = 0;  // |degraded - clean| position over `compared`
  std::vector<double> errors_px;               // the `compared` errors (for pooling over clips)
  std::vector<JumpEvent> jump_events;          // the first kMaxJumpEvents jumps
  static constexpr std::size_t kMaxJumpEvents = 20;

  double lost_fraction() const { return marker_frames ? double(lost) / double(marker_frames) : 0.0; }
  // Adds another clip's counts and errors; call finish() after.
  void merge(const DegradeScore& other);
  void finish();  // rmse/p95/max from errors_px
};

// Scores `degraded` (frame k is source frame source_frame[k]) against `clean` (every source frame).
DegradeScore compare_to_clean(const TrackResult& clean, const TrackResult& degraded,
                              const std::vector<int>& source_frame);

struct DegradeStudy {
  TrackResult clean;
  std::vector<DegradeScore> scores;  // one per degradation, in the order given
};

// Tracks `frames` clean and under each degradation. `progress` is told the fraction of degradations done
// and may cancel between them.
DegradeStudy run_degrade_study(const std::vector<cv::Mat>& frames, const std::vector<Degradation>& degradations,
                               const TrackerOptions& options, const Progress& progress = {});

}  // namespace sb
