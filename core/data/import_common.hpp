#pragma once
// What the importers of raw recordings share: the report they return, a tracked recording wrapped as a dataset,
// and the notes their provenance texts carry.
//
// Axis convention: the sensor camera looks along +z_E from inside the gel, so image u (right) and v (down)
// are already x_E and y_E of a right-handed E with +z out of the gel: no mirroring is applied.
#include <string>
#include <vector>

#include "core/data/tsd_out.hpp"
#include "core/tracking/tracker.hpp"

namespace sb {

struct ImportReport {
  std::vector<std::string> datasets;  // directories written
  std::vector<std::string> lines;     // one human-readable line per recording (lost fraction, warnings)
};

// Wraps one tracked recording as a tsd/1 dataset: motion `free`, pose_known false, placeholder identity
// poses (said so in provenance), markers_rest_px from the tracker's rest estimate.
TsdDatasetOut dataset_from_track(const TrackResult& track, const std::string& name, const std::string& sample_id,
                                 double dt_s, double mm_per_px, const std::string& source_note);

// One line on a tracked recording: frames, markers, grid, pitch and the lost fraction.
std::string track_summary(const TrackResult& track);

// Throws InputError(dir) unless `dir` is a directory.
void require_input_dir(const std::string& dir);

// The provenance notes on the axes (no mirroring) and on unknown poses (identity placeholders, a proxy indenter).
extern const char* const kImportAxisNote;
extern const char* const kImportPoseNote;

}  // namespace sb
