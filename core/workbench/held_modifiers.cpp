#include "core/workbench/held_modifiers.hpp"

namespace sb {

int HeldModifiers::mods() const {
  int m = 0;
  if (down_[kLeftShift] || down_[kRightShift]) m |= kShift;
  if (down_[kLeftCtrl] || down_[kRightCtrl]) m |= kCtrl;
  return m;
}

}  // namespace sb
