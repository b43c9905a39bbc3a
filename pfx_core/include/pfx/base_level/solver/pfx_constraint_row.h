// One scalar constraint of the solver: an impulse along m_normal, clamped to
// [m_lowerLimit, m_upperLimit], accumulated over iterations and kept for warm starting.
#pragma once

#include "pfx/base_level/base/pfx_vec_math.h"

namespace pfx {

struct PfxConstraintRow {
  PfxVector3 m_normal;
  PfxFloat m_rhs;          // impulse that would reach the target velocity from rest
  PfxFloat m_jacDiagInv;   // effective mass along the row
  PfxFloat m_lowerLimit;
  PfxFloat m_upperLimit;
  PfxFloat m_accumImpulse;
};

}  // namespace pfx
