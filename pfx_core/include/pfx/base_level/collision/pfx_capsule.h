// A capsule along the local X axis: a segment of half length m_halfLen swept by a sphere.
#pragma once

#include "pfx/base_level/base/pfx_common.h"

namespace pfx {

struct PfxCapsule {
  PfxFloat m_halfLen = 0;
  PfxFloat m_radius = 0;

  PfxCapsule() = default;
  PfxCapsule(PfxFloat halfLength, PfxFloat radius) : m_halfLen(halfLength), m_radius(radius) {}
};

}  // namespace pfx
