#pragma once
// The FOTS marker calibration pair (raw/fots_marker_calib) imported as one tsd/1 dataset.
#include <string>

#include "core/data/import_common.hpp"

namespace sb {

// raw/fots_marker_calib: one dataset, samples "press" and "shear" (frame 0 rest, frame 1 the CSV field),
// indenter pose estimated from the marker field (see SphereContactEstimate).
ImportReport import_fots(const std::string& in_dir, const std::string& out_dir);

}  // namespace sb
