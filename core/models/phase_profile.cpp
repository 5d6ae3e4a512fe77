#include "core/models/phase_profile.hpp"

namespace sb {

const char* phase_name(Phase phase) {
  switch (phase) {
    case Phase::TransformCull: return "transform+cull";
    case Phase::Sdf: return "sdf";
    case Phase::State: return "state step";
    case Phase::Shear: return "shear sum";
    case Phase::Dilation: return "dilation";
  }
  return "?";
}

}  // namespace sb
