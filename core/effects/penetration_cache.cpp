#include "core/effects/penetration_cache.hpp"

#include <array>
#include <cstring>
#include <map>
#include <mutex>
#include <unordered_map>
#include <utility>

namespace sb {

namespace {

using PoseBits = std::array<double, 12>;  // the rotation and the translation, compared bit for bit

struct PoseBitsHash {
  std::size_t operator()(const PoseBits& k) const {
    std::size_t h = 1469598103934665603ull;
    for (const double d : k) {
      std::uint64_t u = 0;
      std::memcpy(&u, &d, sizeof u);
      h = (h ^ u) * 1099511628211ull;
    }
    return h;
  }
};

struct PoseBitsEqual {
  bool operator()(const PoseBits& a, const PoseBits& b) const { return std::memcmp(a.data(), b.data(), sizeof a) == 0; }
};

PoseBits bits_of(const Pose& X) {
  PoseBits k{};
  const auto& M = X.matrix();
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 3; ++r) k[static_cast<std::size_t>(3 * c + r)] = M(r, c);
  return k;
}

struct PairCache {
  std::weak_ptr<const Sensor> sensor;
  std::weak_ptr<const Indenter> indenter;
  std::unordered_map<PoseBits, Penetration, PoseBitsHash, PoseBitsEqual> poses;
};

struct Caches {
  std::mutex mutex;
  std::map<std::pair<const Sensor*, const Indenter*>, PairCache> pairs;
};

Caches& caches() {
  static Caches c;
  return c;
}

// The pair's cache, emptied when the objects at these addresses are not the ones it was made for. Caller holds the
// mutex.
PairCache& pair_cache(Caches& c, const std::shared_ptr<const Sensor>& sensor,
                      const std::shared_ptr<const Indenter>& indenter) {
  std::erase_if(c.pairs, [](const auto& e) { return e.second.sensor.expired() || e.second.indenter.expired(); });
  PairCache& p = c.pairs[{sensor.get(), indenter.get()}];
  if (p.sensor.lock() != sensor || p.indenter.lock() != indenter) {
    p.sensor = sensor;
    p.indenter = indenter;
    p.poses.clear();
  }
  return p;
}

}  // namespace

Penetration cached_penetration(const std::shared_ptr<const Sensor>& sensor,
                               const std::shared_ptr<const Indenter>& indenter, const Pose& X_EI) {
  const PoseBits key = bits_of(X_EI);
  Caches& c = caches();
  {
    const std::lock_guard<std::mutex> lock(c.mutex);
    const PairCache& p = pair_cache(c, sensor, indenter);
    if (const auto it = p.poses.find(key); it != p.poses.end()) return it->second;
  }
  const Penetration pen = indenter_penetration(*sensor->gel_sdf, *indenter, X_EI);  // outside the lock: the cost
  const std::lock_guard<std::mutex> lock(c.mutex);
  PairCache& p = pair_cache(c, sensor, indenter);
  if (p.poses.size() >= kPenetrationCacheCapacity) p.poses.clear();
  p.poses.emplace(key, pen);
  return pen;
}

std::size_t penetration_cache_size() {
  Caches& c = caches();
  const std::lock_guard<std::mutex> lock(c.mutex);
  std::size_t n = 0;
  for (const auto& [key, p] : c.pairs)
    if (!p.sensor.expired() && !p.indenter.expired()) n += p.poses.size();
  return n;
}

}  // namespace sb
