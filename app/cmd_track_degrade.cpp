// shearbench track-degrade: the tracker under degraded video. Each clip is tracked clean, then under each
// degradation (blur, noise, brightness drift, JPEG, dropped frames, a sliding occluder), and the degraded
// tracks are scored against the clean one: lost marker-frames, position error on markers tracked in both,
// and jumps (a marker placed off its clean track by more than half a pitch, or on another marker's dot).
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <sstream>

#include "app/command.hpp"
#include "app/interrupt.hpp"
#include "core/base/atomic_write.hpp"
#include "core/base/data_root.hpp"
#include "core/base/error.hpp"
#include "core/tracking/degrade_study.hpp"

namespace fs = std::filesystem;

namespace sb::app {
namespace {

// Three strengths per kind, mild to severe (docs/tracking.md, "Under degradation").
const std::vector<std::string> kDefaultStudy = {
    "blur:1",          "blur:2",         "blur:4",       "noise:5",        "noise:15",      "noise:30",
    "brightness:-0.6", "brightness:0.5", "brightness:1", "jpeg:50",        "jpeg:20",       "jpeg:5",
    "drop:0.25",       "drop:0.5",       "drop:0.75",    "occlusion:0.05", "occlusion:0.1", "occlusion:0.2"};

struct TrackDegradeArgs {
  std::vector<std::string> videos;
  std::vector<std::string> degrade = kDefaultStudy;
  std::string json, markdown;
  int max_frames = 0;
  int seed = 1;
  bool per_clip = false;
};

std::string table_header() {
  return "| degradation | frames seen | marker-frames | lost | RMSE px | p95 px | max px | jumps | onto a neighbour's "
         "dot "
         "| unpaired markers |\n|---|---|---|---|---|---|---|---|---|---|\n";
}

std::string table_row(const DegradeScore& s) {
  char row[320];
  if (s.label == "clean") {  // the reference itself: its own lost fraction, nothing to compare
    std::snprintf(row, sizeof row, "| clean (the reference) | %ld | %ld | %.2f %% | | | | | | |\n", s.frames_seen,
                  s.marker_frames, 100.0 * s.lost_fraction());
    return row;
  }
  std::snprintf(row, sizeof row, "| %s | %ld | %ld | %.2f %% | %.3f | %.3f | %.3f | %ld | %ld | %d |\n",
                s.label.c_str(), s.frames_seen, s.marker_frames, 100.0 * s.lost_fraction(), s.rmse_px, s.p95_px,
                s.max_px, s.jumps, s.onto_neighbour, s.unpaired_markers);
  return row;
}

nlohmann::json score_json(const DegradeScore& s) {
  auto xy = [](const Vec2& p) { return std::isfinite(p.x()) ? nlohmann::json{p.x(), p.y()} : nlohmann::json(nullptr); };
  nlohmann::json events = nlohmann::json::array();
  for (const auto& e : s.jump_events)
    events.push_back({{"frame", e.source_frame},
                      {"marker", e.marker},
                      {"clean_uv", xy(e.clean_uv)},
                      {"degraded_uv", xy(e.degraded_uv)},
                      {"onto_marker", e.onto_marker}});
  return {{"jump_events", events},
          {"degradation", s.label},
          {"frames_seen", s.frames_seen},
          {"marker_frames", s.marker_frames},
          {"lost", s.lost},
          {"lost_fraction", s.lost_fraction()},
          {"compared", s.compared},
          {"rmse_px", s.rmse_px},
          {"p95_px", s.p95_px},
          {"max_px", s.max_px},
          {"jumps", s.jumps},
          {"onto_neighbour", s.onto_neighbour},
          {"unverified", s.unverified},
          {"unpaired_markers", s.unpaired_markers}};
}

int run_track_degrade(const TrackDegradeArgs& a, const GlobalOptions& g) {
  if (a.videos.empty()) throw InputError("track-degrade", "give at least one --video FILE");
  std::vector<Degradation> degradations;
  for (const auto& text : a.degrade) {
    Degradation d = parse_degradation(text, "--degrade");
    d.seed = static_cast<std::uint64_t>(a.seed);
    degradations.push_back(d);
  }
  const std::string root = resolve_data_root(g.data_root_flag);
  InterruptScope interrupt;  // Ctrl-C: sb::Cancelled, exit 130, nothing written
  Progress progress;
  progress.cancel = interrupt.flag();

  const TrackerOptions options;
  std::vector<DegradeScore> total(degradations.size());
  DegradeScore clean_total;
  clean_total.label = "clean";
  nlohmann::json clips = nlohmann::json::array();
  std::ostringstream per_clip;
  for (const auto& video : a.videos) {
    const std::string path = resolve_path(video, root, "");
    std::vector<cv::Mat> frames = read_video_frames(path);
    if (a.max_frames > 0 && static_cast<int>(frames.size()) > a.max_frames) frames.resize(a.max_frames);
    if (!g.quiet) std::fprintf(stderr, "%s: %zu frames\n", video.c_str(), frames.size());
    const DegradeStudy study = run_degrade_study(frames, degradations, options, progress);
    DegradeScore clean;
    clean.label = "clean";
    clean.frames_seen = study.clean.frames();
    for (const auto& f : study.clean.disp_px)
      for (const auto& d : f) {
        ++clean.marker_frames;
        clean.lost += std::isfinite(d.x()) ? 0 : 1;
      }
    clean_total.merge(clean);
    nlohmann::json rows = nlohmann::json::array();
    per_clip << "\n"
             << video << " (" << study.clean.markers() << " markers, pitch " << study.clean.pitch_px << " px)\n\n"
             << table_header() << table_row(clean);
    for (std::size_t d = 0; d < degradations.size(); ++d) {
      total[d].label = study.scores[d].label;
      total[d].merge(study.scores[d]);
      rows.push_back(score_json(study.scores[d]));
      per_clip << table_row(study.scores[d]);
    }
    clips.push_back({{"video", video},
                     {"frames", study.clean.frames()},
                     {"markers", study.clean.markers()},
                     {"pitch_px", study.clean.pitch_px},
                     {"clean_lost_fraction", study.clean.lost_fraction()},
                     {"degraded", rows}});
  }

  // "clean" row: the reference's own lost fraction (what the degraded rows' marker-frames are out of).
  std::ostringstream md;
  md << table_header() << table_row(clean_total);
  nlohmann::json totals = nlohmann::json::array();
  for (auto& s : total) {
    s.finish();
    md << table_row(s);
    totals.push_back(score_json(s));
  }
  std::printf("%s", md.str().c_str());
  if (a.per_clip) std::printf("%s", per_clip.str().c_str());
  if (!a.markdown.empty()) write_file_atomic(a.markdown, md.str() + (a.per_clip ? per_clip.str() : ""));
  if (!a.json.empty()) {
    const nlohmann::json j = {{"format", "shearbench-track-degrade/1"},
                              {"seed", a.seed},
                              {"max_frames", a.max_frames},
                              {"jump_pitch", kJumpPitch},
                              {"pair_pitch", kStudyPairPitch},
                              {"pooled", totals},
                              {"clips", clips}};
    write_file_atomic(a.json, j.dump(1) + "\n");
  }
  return 0;
}

// "blur (px, 0-10): Gaussian blur sigma; ..." from the one table of degradations.
std::string kinds_help() {
  std::string h;
  const ParamSet specs = degrade_param_specs();
  for (const ParamSpec& s : specs.specs()) {
    char line[200];
    std::snprintf(line, sizeof line, "\n  %s (%s%s%g..%g): %s", s.name.c_str(), s.unit.c_str(),
                  s.unit.empty() ? "" : ", ", s.min, s.max, s.help.c_str());
    h += line;
  }
  return h;
}

void add_flags(CLI::App& sub, TrackDegradeArgs& a) {
  sub.add_option("--video", a.videos, "input video(s); data:... resolves through the data root")->required();
  sub.add_option("--degrade", a.degrade,
                 "KIND:STRENGTH, repeatable (default: three strengths of each kind):" + kinds_help())
      ->capture_default_str();
  sub.add_option("--max-frames", a.max_frames, "track only the first N frames of each clip (0 = all)")
      ->capture_default_str();
  sub.add_option("--seed", a.seed, "seed of the noise and of the dropped frames")->capture_default_str();
  sub.add_option("--json", a.json, "write every clip's and the pooled scores as JSON (atomically)");
  sub.add_option("--markdown", a.markdown, "write the table as Markdown (atomically)");
  sub.add_flag("--per-clip", a.per_clip, "also print one table per clip");
}

const Subcommand<TrackDegradeArgs> kTrackDegradeCommand{
    "track-degrade",
    "the marker tracker under blur, noise, drift, JPEG, dropped frames and occlusion, vs the clean track", 41,
    add_flags, run_track_degrade};

}  // namespace
}  // namespace sb::app
