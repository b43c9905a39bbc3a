// A cylinder along the local X axis with half length m_halfLen and radius m_radius.
#pragma once

#include "pfx/base_level/base/pfx_common.h"

namespace pfx {

struct PfxCylinder {
  PfxFloat m_halfLen = 0;
  PfxFloat m_radius = 0;

  PfxCylinder() = default;
  PfxCylinder(PfxFloat halfLength, PfxFloat radius) : m_halfLen(halfLength), m_radius(radius) {}
};

}  // namespace pfx
