#pragma once
// The indenter's penetration remembered across models (EffectModel): the loop builds a fresh model per sample for
// every score, recording and fingerprint, and on the TacTip (a 15k-point flat surface) computing the penetration
// again each time was a sixth of the loop's CPU time. The value is a pure function of the gel, the indenter and
// the pose, so a remembered one for bit-identical arguments is the same value.
#include <cstddef>
#include <memory>

#include "core/effects/effects.hpp"
#include "core/sensor/sensor.hpp"

namespace sb {

// Remembers at most this many poses per (sensor, indenter) pair; past that it starts again (a pose effect being
// fitted makes every run's poses new, and those are not worth keeping).
inline constexpr std::size_t kPenetrationCacheCapacity = 1 << 18;

// indenter_penetration(*sensor->gel_sdf, *indenter, X_EI), from the cache when this pair saw this exact pose.
// Thread-safe. The cache keeps no sensor or indenter alive: an entry is dropped once either expires, and a new one
// at a freed one's address starts empty. @pre sensor and indenter are not null, sensor->gel_sdf is set.
Penetration cached_penetration(const std::shared_ptr<const Sensor>& sensor,
                               const std::shared_ptr<const Indenter>& indenter, const Pose& X_EI);

// Poses remembered over all pairs (for tests).
std::size_t penetration_cache_size();

}  // namespace sb
