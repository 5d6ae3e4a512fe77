#pragma once
// The GelSight Mini video importers: each recording tracked into its own tsd/1 dataset.
#include <string>

#include "core/data/import_common.hpp"
#include "core/tracking/tracker.hpp"

namespace sb {

// raw/gsrobotics_tracking: one dataset per video (video_N.avi, mini_example.avi) under out_dir/<stem>/,
// because tsd/1 has one markers_rest_px per dataset and each recording has its own rest.
// keep_frames: also store the decoded video frames (frames/NNNNNN.png) so the workbench shows the real image.
ImportReport import_gsrobotics(const std::string& in_dir, const std::string& out_dir, const TrackerOptions& opts,
                               double mm_per_px, bool keep_frames = false);
// raw/incipient_slip: one dataset per clip under out_dir/<experiment>_<camera>/, sample field
// "slip_label" = true when the experiment folder holds slip.txt.
ImportReport import_incipient_slip(const std::string& in_dir, const std::string& out_dir, const TrackerOptions& opts,
                                   double mm_per_px, bool keep_frames = false);

}  // namespace sb
