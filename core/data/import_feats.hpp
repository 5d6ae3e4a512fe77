#pragma once
// The FEATS sample (raw/feats: a cuboid pressed into a GelSight Mini) imported as one tsd/1 dataset.
#include <string>

#include "core/data/import_common.hpp"

namespace sb {

// raw/feats: one dataset, sample "cuboid_contact" with frames [nocontact, contact] and tracked markers.
ImportReport import_feats(const std::string& in_dir, const std::string& out_dir);

}  // namespace sb
