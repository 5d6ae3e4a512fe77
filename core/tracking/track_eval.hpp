#pragma once
// Accuracy of a TrackResult against a reference: the vendor tracker's marker_locations CSV (gsrobotics), or
// a tsd/1 sample with exact displacements (twin_frames). Markers are paired by nearest rest position.
#include <string>
#include <vector>

#include "core/tracking/tracker.hpp"

namespace sb {

struct TrackComparison {
  int pairs = 0;              // marker-frames compared (both sides finite)
  int reference_markers = 0;  // markers in the reference
  int paired_markers = 0;     // reference markers with a tracked marker at rest
  int lost = 0;               // marker-frames the tracker lost where the reference has a value
  double rmse_px = 0, median_px = 0, p95_px = 0, max_px = 0;
  Vec2 mean_rest_offset_px = Vec2::Zero();  // tracked rest - reference rest, mean over paired markers
  // Displacements only (each side relative to its own rest), which removes a constant difference between
  // two detectors' definitions of a dot centre: the tracking error proper.
  double disp_rmse_px = 0, disp_median_px = 0, disp_p95_px = 0, disp_max_px = 0;
};

// The vendor CSV: rows `frame, row, col, x0, y0, x, y` (no header), frames numbered from 1.
struct VendorTrack {
  int frames = 0;
  std::vector<Vec2> rest_px;                   // x0, y0 of each (row, col) marker, row-major
  std::vector<std::vector<Vec2>> position_px;  // [frame - 1][marker] x, y
};
VendorTrack read_vendor_csv(const std::string& path);

// Compares tracked positions (rest + displacement) of frame f + frame_offset with vendor frame f + 1.
TrackComparison compare_to_vendor(const TrackResult& tracked, const VendorTrack& vendor, int frame_offset = 0);

// Reads `frame,marker,du_px,dv_px` (nan allowed) into [frame][marker].
std::vector<std::vector<Vec2>> read_markers_csv(const std::string& path, int markers);

// Compares absolute positions (tracked rest + disp vs reference rest + reference disp).
// `remove_rest_offset`: compare displacement fields only (tracked disp vs reference disp).
TrackComparison compare_to_reference(const TrackResult& tracked, const std::vector<Vec2>& reference_rest_px,
                                     const std::vector<std::vector<Vec2>>& reference_disp_px, bool remove_rest_offset);

}  // namespace sb
