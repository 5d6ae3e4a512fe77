// shearbench track: follows the markers of a video or a frames directory and writes a tsd/1 dataset
// (motion free, pose unknown). With --reference-vendor / --reference-tsd it also reports the accuracy.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "app/command.hpp"
#include "app/interrupt.hpp"
#include "core/base/atomic_write.hpp"
#include "core/base/error.hpp"
#include "core/data/importers.hpp"
#include "core/data/tsd.hpp"
#include "core/tracking/track_eval.hpp"
#include "core/tracking/tracker.hpp"

namespace fs = std::filesystem;

namespace sb::app {
namespace {

struct TrackArgs {
  std::string video, frames, out, grid = "auto", reference_vendor, reference_tsd, draw;
  double mm_per_px = 0.0634;
  int rest_frames = TrackerOptions{}.rest_frames;
  int vendor_frame_offset = 0;
};

void print_comparison(const std::string& what, const TrackComparison& c) {
  std::printf(
      "%s: %d marker-frames, %d/%d markers paired, lost %d, RMSE %.3f px, median %.3f px, "
      "p95 %.3f px, max %.3f px, rest offset (%.3f, %.3f) px\n",
      what.c_str(), c.pairs, c.paired_markers, c.reference_markers, c.lost, c.rmse_px, c.median_px, c.p95_px, c.max_px,
      c.mean_rest_offset_px.x(), c.mean_rest_offset_px.y());
  std::printf("  displacements: RMSE %.3f px, median %.3f px, p95 %.3f px, max %.3f px\n", c.disp_rmse_px,
              c.disp_median_px, c.disp_p95_px, c.disp_max_px);
}

// Annotated copies of the frames: tracked positions (green), lost markers at their rest (red).
void draw_frames(const std::vector<cv::Mat>& frames, const TrackResult& r, const std::string& dir) {
  fs::create_directories(dir);
  for (int f = 0; f < std::min<int>(r.frames(), static_cast<int>(frames.size())); ++f) {
    cv::Mat big;
    cv::resize(frames[f], big, {}, 3, 3, cv::INTER_NEAREST);
    for (int m = 0; m < r.markers(); ++m) {
      const Vec2 d = r.disp_px[f][m];
      const bool ok = std::isfinite(d.x());
      const Vec2 p = 3.0 * ((ok ? Vec2(r.rest_px[m] + d) : r.rest_px[m]) + Vec2(0.5, 0.5));
      cv::circle(big, cv::Point(int(p.x()), int(p.y())), ok ? 4 : 8, ok ? cv::Scalar(0, 255, 0) : cv::Scalar(0, 0, 255),
                 1);
      cv::putText(big, std::to_string(m), cv::Point(int(p.x()) + 5, int(p.y()) - 5), cv::FONT_HERSHEY_PLAIN, 0.8,
                  cv::Scalar(255, 255, 255));
    }
    write_png_atomic((fs::path(dir) / frame_file_name(f)).string(), big.rows, big.cols, big.channels(), big.data);
  }
}

// The tsd sample directory's dataset.json is its parent's.
void compare_tsd(const TrackResult& r, const std::string& sample_dir) {
  // The validated reader: a malformed dataset.json is an InputError naming the file and the entry.
  const std::vector<Vec2> rest = read_dataset(fs::path(sample_dir).parent_path().string()).markers_rest_px;
  const auto disp = read_markers_csv((fs::path(sample_dir) / "markers.csv").string(), static_cast<int>(rest.size()));
  print_comparison("vs reference positions (rest + disp)", compare_to_reference(r, rest, disp, false));
  print_comparison("vs reference displacements", compare_to_reference(r, rest, disp, true));
}

int run_track(const TrackArgs& a, const GlobalOptions& g) {
  if (a.video.empty() && a.frames.empty()) throw InputError("track", "give --video FILE or --frames DIR");
  TrackerOptions opts;
  parse_grid(a.grid, "--grid", opts);
  opts.rest_frames = a.rest_frames;
  const auto t0 = std::chrono::steady_clock::now();
  InterruptScope interrupt;  // Ctrl-C: sb::Cancelled, exit 130, nothing written
  Progress progress;
  progress.cancel = interrupt.flag();
  progress.report = [](const std::string& what, double fraction) {
    if (fraction >= 0) std::fprintf(stderr, "%s: %3.0f%%\n", what.c_str(), 100.0 * fraction);
  };
  const TrackResult r = !a.video.empty() ? track_video(a.video, opts, progress)
                                         : track_frames_dir(a.frames, opts, progress);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf(
      "tracked %d frames, %d markers (grid %dx%d, pitch %.2f px), lost %.4f of marker-frames, "
      "%.0f frames/s including decoding\n",
      r.frames(), r.markers(), r.grid_rows, r.grid_cols, r.pitch_px, r.lost_fraction(), r.frames() / seconds);
  for (const auto& w : r.warnings) std::printf("warning: %s\n", w.c_str());

  if (!a.out.empty()) {
    const std::string source = !a.video.empty() ? a.video : a.frames;
    const std::string stem = fs::path(source).filename().replace_extension().string();
    const auto ds = dataset_from_track(r, stem, stem.empty() ? "recording" : stem, 0.04, a.mm_per_px,
                                       "tracked by `shearbench track` from " + source + " (grid " + a.grid + ")");
    write_tsd_dataset(ds, a.out);
    if (!g.quiet) std::printf("wrote %s\n", a.out.c_str());
  }
  if (!a.reference_vendor.empty())
    print_comparison("vs vendor tracker",
                     compare_to_vendor(r, read_vendor_csv(a.reference_vendor), a.vendor_frame_offset));
  if (!a.reference_tsd.empty()) compare_tsd(r, a.reference_tsd);
  if (!a.draw.empty() && !a.video.empty()) draw_frames(read_video_frames(a.video), r, a.draw);
  return 0;
}

void add_flags(CLI::App& sub, TrackArgs& a) {
  auto* video = sub.add_option("--video", a.video, "input video (e.g. .avi)");
  auto* frames = sub.add_option("--frames", a.frames, "input frames directory (NNNNNN.png)");
  video->excludes(frames);
  sub.add_option("--out", a.out, "output tsd/1 dataset directory");
  sub.add_option("--grid", a.grid, "marker grid ROWSxCOLS (7x9, 8x10, 11x9) or auto")->capture_default_str();
  sub.add_option("--mm-per-px", a.mm_per_px, "image scale written to the dataset")->capture_default_str();
  sub.add_option("--rest-frames", a.rest_frames, "frames whose median is the rest")->capture_default_str();
  sub.add_option("--reference-vendor", a.reference_vendor, "vendor marker_locations CSV to compare with");
  sub.add_option("--vendor-frame-offset", a.vendor_frame_offset, "our frame = vendor frame - 1 + offset");
  sub.add_option("--draw", a.draw, "write annotated frames (3x) into this directory (videos)");
  sub.add_option("--reference-tsd", a.reference_tsd, "tsd/1 sample directory with exact markers.csv");
}

const Subcommand<TrackArgs> kTrackCommand{
    "track", "track the markers of a video or frames directory into a tsd/1 dataset", 40, add_flags, run_track};

}  // namespace
}  // namespace sb::app
