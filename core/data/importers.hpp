#pragma once
// Converters from the raw recordings in <data>/raw/ into tsd/1 (FORMAT.md), one header per source, gathered here for
// the CLI. Each records in `provenance` what was done: source files, scale, grid, axis convention, and for unknown
// poses how they were estimated.
#include "core/data/import_common.hpp"
#include "core/data/import_feats.hpp"
#include "core/data/import_fots.hpp"
#include "core/data/import_gelsight_video.hpp"
#include "core/data/import_tactip.hpp"
#include "core/data/obj_writers.hpp"
#include "core/data/sphere_contact.hpp"
#include "core/data/tactip_targets.hpp"
