#include "core/models/phase_profile.hpp"

namespace sb {

const char* phase_name(Phase phase) {
  switch (phase) {
    case Phase::kTransformCull: return "transform+cull";
    case Phase::kSdf: return "sdf";
    case Phase::kState: return "state step";
    case Phase::kShear: return "shear sum";
    case Phase::kDilation: return "dilation";
  }
  return "?";
}

}  // namespace sb
