#pragma once
// Where a batched model step spends its time. A batch given a PhaseProfile (set_profile) times its
// phases with a per-task lap clock and adds the CPU-side nanoseconds (summed over worker threads) at
// the end of each parallel task; with no profile set, the clock does nothing (one null test per lap).
#include <array>
#include <atomic>
#include <chrono>
#include <cstdint>

namespace sb {

// The phases of one batched step, for every model:
//   TransformCull  markers into I / indenter points into E, and the cluster cull (HydroShear)
//   Sdf            the SDF lookups (phi_E of the points, phi_I of the markers)
//   State          the state step (HydroShear tracker, FOTS anchors and SE(2), TacSL velocities)
//   Shear          the shear (and twist) sum over the markers
//   Dilation       the dilation sum and the output write
enum class Phase : int { kTransformCull = 0, kSdf, kState, kShear, kDilation };
inline constexpr int kPhaseCount = 5;
const char* phase_name(Phase phase);

struct PhaseProfile {
  std::array<std::atomic<std::int64_t>, kPhaseCount> ns{};
  void clear() {
    for (auto& v : ns) v.store(0, std::memory_order_relaxed);
  }
  double ms(Phase p) const { return 1e-6 * static_cast<double>(ns[static_cast<int>(p)].load()); }
};

// A lap clock owned by one parallel task: lap(phase) charges the time since the previous lap to phase.
class PhaseClock {
 public:
  using Clock = std::chrono::steady_clock;
  explicit PhaseClock(PhaseProfile* profile) : profile_(profile) {
    if (profile_) last_ = Clock::now();
  }
  PhaseClock(const PhaseClock&) = delete;
  PhaseClock& operator=(const PhaseClock&) = delete;
  ~PhaseClock() {
    if (!profile_) return;
    for (int i = 0; i < kPhaseCount; ++i)
      if (local_[i] != 0) profile_->ns[i].fetch_add(local_[i], std::memory_order_relaxed);
  }
  void lap(Phase phase) {
    if (!profile_) return;
    const Clock::time_point now = Clock::now();
    local_[static_cast<int>(phase)] += std::chrono::duration_cast<std::chrono::nanoseconds>(now - last_).count();
    last_ = now;
  }

 private:
  PhaseProfile* profile_;
  Clock::time_point last_{};
  std::array<std::int64_t, kPhaseCount> local_{};
};

}  // namespace sb
