#pragma once
// Marker tracker for GelSight-type images: dark dots on a bright, coloured, shaded background.
//
// Detection (per frame): brightness = max(B, G, R) (a dot is dark in every channel, the coloured background
// is bright in at least one); the vendor's red overlay arrows, when present, are masked and filled from the pixels
// around them; the shading is removed by a black top-hat (closing with a box larger than a dot, minus the image)
// divided by the closed background, i.e. the relative darkness; Otsu threshold (with a floor); connected components
// filtered by area; sub-pixel centre = darkness-weighted centroid over the blob grown by one pixel.
//
// Correspondence (per frame): each marker's displacement is predicted from its own last displacement and
// velocity (lost markers: from their neighbours' displacements); detections are assigned one-to-one by a
// greedy sort of all marker/detection pairs inside a gate, taking a detection only when it is clearly the
// nearest (ratio test). A smooth-field pass then re-predicts every marker whose match disagrees with the
// median of its rest-neighbours and matches again. Last, matches that contradict the field are dropped: a
// marker far from its neighbours' median, and any group of markers whose displacements jump by more than
// half a pitch against a larger group next to it (a block that slipped onto its neighbours' dots). A marker
// with no unambiguous detection inside the gate is lost (NaN) for that frame and may be re-acquired later:
// under degraded video the tracker loses markers rather than give them a neighbour's dot.
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "core/base/params.hpp"
#include "core/base/progress.hpp"
#include "core/geometry/pose.hpp"

namespace sb {

struct MarkerDetection {
  Vec2 uv;         // sub-pixel centre, pixels (pixel centres at integer coordinates, OpenCV convention)
  double area_px;  // thresholded blob area
  bool touches_border;
};

struct TrackerOptions {
  // Grid: rows x cols expected (0 = auto: whatever the rest frames show). Used for a consistency
  // warning only; the tracker follows every marker it sees at rest.
  int grid_rows = 0;
  int grid_cols = 0;
  int rest_frames = 3;                   // rest = per-marker median over the first rest_frames frames
  double max_dot_diameter_px = 24;       // top-hat box is 1.3x this
  double min_contrast = 0.12;            // lowest relative darkness accepted as a dot (threshold floor)
  double min_area_px = 12;               // smaller blobs are noise
  double max_area_factor = 2.2;          // blobs larger than this x the median area are merged dots: rejected
  double min_border_area_factor = 0.45;  // a blob cut by the image border must keep this much of the area
  double gate_fraction = 0.45;           // match gate, fraction of the rest pitch
  double velocity_gain = 0.7;            // prediction = last displacement + gain * last velocity
  bool remove_overlay = true;            // mask saturated red drawing (the vendor's arrows) before detecting
};

// The tracker's tunables, described once (name, unit, default, range).
ParamSet tracker_param_specs();

// Parses "7x9", "8x10", "11x9" or "auto" (rows x cols). Throws InputError(where) for anything else.
void parse_grid(const std::string& text, const std::string& where, TrackerOptions& options);

// Detects the dots of one BGR (or grey) frame.
std::vector<MarkerDetection> detect_markers(const cv::Mat& frame, const TrackerOptions& options);

struct TrackResult {
  int grid_rows = 0;  // rows/cols found at rest (rows: clusters of v), 0 when irregular
  int grid_cols = 0;
  double pitch_px = 0;                     // median nearest-neighbour distance at rest
  std::vector<Vec2> rest_px;               // marker index -> rest position, row-major (v, then u)
  std::vector<std::vector<Vec2>> disp_px;  // [frame][marker] displacement from rest, NaN when lost
  std::vector<std::string> warnings;
  int image_width = 0, image_height = 0;

  int frames() const { return static_cast<int>(disp_px.size()); }
  int markers() const { return static_cast<int>(rest_px.size()); }
  double lost_fraction() const;  // NaN marker-frames / all marker-frames
};

// Incremental tracker: feed frames in order, then take the result.
class MarkerTracker {
 public:
  explicit MarkerTracker(TrackerOptions options = {});
  void add_frame(const cv::Mat& frame);
  // Finishes the rest estimate when fewer than rest_frames frames were given.
  TrackResult result();

 private:
  void initialise_rest();
  void track(const std::vector<MarkerDetection>& detections, std::vector<Vec2>& disp_out);
  std::vector<Vec2> predict(const std::vector<Vec2>& previous) const;
  // Displacements of the detections assigned to markers predicted at `predicted` (NaN: none).
  std::vector<Vec2> match(const std::vector<Vec2>& predicted, const std::vector<MarkerDetection>& det) const;
  std::vector<Vec2> grow(const std::vector<Vec2>& first, const std::vector<Vec2>& pred,
                         const std::vector<MarkerDetection>& det) const;
  void drop_contradicted(std::vector<Vec2>& disp) const;
  // Per marker: the median displacement of its finite rest-neighbours (NaN with fewer than min_count).
  std::vector<Vec2> neighbour_median(const std::vector<Vec2>& disp, std::size_t min_count = 2) const;

  TrackerOptions options_;
  std::vector<std::vector<MarkerDetection>> pending_;  // detections of the rest frames
  TrackResult result_;
  bool initialised_ = false;
  std::vector<std::vector<int>> neighbours_;  // rest-neighbours of each marker (smooth-field prior)
  std::vector<std::vector<int>> adjacent_;    // nearest rest-neighbours (lattice-slip check)
  std::vector<Vec2> velocity_;
  std::vector<int> last_seen_;  // frame index a marker was last matched, -1 never
};

// Whole sequences. Unreadable or empty inputs throw InputError naming the path.
TrackResult track_frames(const std::vector<cv::Mat>& frames, const TrackerOptions& options);
// `progress` is told the fraction of frames done; a set cancel flag throws sb::Cancelled.
TrackResult track_video(const std::string& path, const TrackerOptions& options, const Progress& progress = {});
// frames_dir holds NNNNNN.png (any image files, sorted by name).
TrackResult track_frames_dir(const std::string& frames_dir, const TrackerOptions& options,
                             const Progress& progress = {});
// Reads every frame of a video (InputError naming it when it cannot be opened or has no frame).
std::vector<cv::Mat> read_video_frames(const std::string& path);

}  // namespace sb
