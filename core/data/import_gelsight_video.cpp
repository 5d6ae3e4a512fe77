// The GelSight Mini video importers (import_gelsight_video.hpp).
#include "core/data/import_gelsight_video.hpp"

#include <algorithm>
#include <filesystem>
#include <opencv2/videoio.hpp>

#include "core/base/error.hpp"
#include "core/base/format.hpp"

namespace fs = std::filesystem;

namespace sb {

namespace {

constexpr double kDefaultFps = 25.0;

double video_dt_s(const std::string& path) {
  cv::VideoCapture cap(path, cv::CAP_FFMPEG);  // FFmpeg only: no GStreamer or image-sequence guesses
  const double fps = cap.isOpened() ? cap.get(cv::CAP_PROP_FPS) : 0.0;
  return 1.0 / (fps > 1.0 && fps < 1000.0 ? fps : kDefaultFps);
}

// Tracks one video into its own dataset directory; a video that cannot be read is reported, not fatal.
void import_video(const std::string& video, const std::string& out, const std::string& name, const TrackerOptions& opts,
                  double mm_per_px, const std::string& origin, const std::string& license, nlohmann::json extra,
                  ImportReport& report, bool keep_frames) {
  TrackResult r;
  try {
    r = track_video(video, opts);
  } catch (const InputError& e) {
    report.lines.push_back(name + ": skipped, " + e.what());
    return;
  }
  std::string note = origin + " Tracked with shearbench's marker tracker (rest = median of the first " +
                     std::to_string(opts.rest_frames) + " frames, grid auto-detected: " + track_summary(r) +
                     "). Scale " + format_number(mm_per_px, "%.4f") +
                     " mm/px (vendor README), principal point the image centre. " + kImportAxisNote + " " +
                     kImportPoseNote;
  for (const auto& w : r.warnings) note += " Tracker warning: " + w + ".";
  TsdDatasetOut ds = dataset_from_track(r, name, name, video_dt_s(video), mm_per_px, note);
  ds.license = license;
  ds.samples.front().extra = std::move(extra);
  if (keep_frames) {
    std::vector<cv::Mat> frames = read_video_frames(video);
    frames.resize(std::min<std::size_t>(frames.size(), static_cast<std::size_t>(r.frames())));
    if (frames.size() == static_cast<std::size_t>(r.frames()))
      ds.samples.front().frames = std::move(frames);
    else
      report.lines.push_back(name + ": frames not stored (decoded " + std::to_string(frames.size()) + " of " +
                             std::to_string(r.frames()) + ")");
  }
  write_tsd_dataset(ds, out);
  report.datasets.push_back(out);
  report.lines.push_back(name + ": " + track_summary(r));
}

}  // namespace

ImportReport import_gsrobotics(const std::string& in_dir, const std::string& out_dir, const TrackerOptions& opts,
                               double mm_per_px, bool keep_frames) {
  require_input_dir(in_dir);
  std::vector<fs::path> videos;
  for (const auto& e : fs::directory_iterator(in_dir))
    if (e.path().extension() == ".avi") videos.push_back(e.path());
  std::sort(videos.begin(), videos.end());
  if (videos.empty()) throw InputError(in_dir, "no .avi recordings");
  ImportReport report;
  for (const auto& v : videos) {
    const std::string stem = v.stem().string();
    const std::string origin = "GelSight Mini recording " + v.filename().string() +
                               " from gelsightinc/gsrobotics (GPL-3.0), see raw/gsrobotics_tracking/SOURCE.md; contact "
                               "is a human fingertip (no indenter geometry, pose or force)." +
                               (stem.rfind("video_", 0) == 0 ? " The video carries the vendor tracker's red arrows; "
                                                               "the tracker masks and fills them before detecting."
                                                             : "");
    import_video(v.string(), (fs::path(out_dir) / stem).string(), "gsrobotics_" + stem, opts, mm_per_px, origin,
                 "GPL-3.0", nlohmann::json::object(), report, keep_frames);
  }
  return report;
}

ImportReport import_incipient_slip(const std::string& in_dir, const std::string& out_dir, const TrackerOptions& opts,
                                   double mm_per_px, bool keep_frames) {
  require_input_dir(in_dir);
  std::vector<fs::path> experiments;
  for (const auto& e : fs::directory_iterator(in_dir))
    if (e.is_directory()) experiments.push_back(e.path());
  std::sort(experiments.begin(), experiments.end());
  ImportReport report;
  for (const auto& exp : experiments) {
    const bool slip = fs::exists(exp / "slip.txt");
    std::vector<fs::path> clips;
    for (const auto& e : fs::directory_iterator(exp))
      if (e.path().extension() == ".avi") clips.push_back(e.path());
    std::sort(clips.begin(), clips.end());
    for (const auto& clip : clips) {
      const std::string name = exp.filename().string() + "_" + clip.stem().string();
      const std::string origin =
          "Incipient-slip grasp recording " + exp.filename().string() + "/" + clip.filename().string() +
          " from amitparag/Incipient-Slip-Detection (BSD-2-Clause), see raw/incipient_slip/SOURCE.md: a GelSight "
          "Mini fingertip of a Franka gripper grasping, lifting and shaking a household object. Sample field "
          "slip_label: true when the experiment folder holds slip.txt (the authors labelled the run as containing "
          "slip), false otherwise (no slip label).";
      import_video(clip.string(), (fs::path(out_dir) / name).string(), name, opts, mm_per_px, origin, "BSD-2-Clause",
                   nlohmann::json{{"slip_label", slip}}, report, keep_frames);
    }
  }
  if (report.lines.empty()) throw InputError(in_dir, "no experiment folders with .avi clips");
  return report;
}

}  // namespace sb
