// A box, represented by its half extents along the local X, Y and Z axes.
#pragma once

#include "pfx/base_level/base/pfx_vec_math.h"

namespace pfx {

struct PfxBox {
  PfxVector3 m_half = PfxVector3::Zero();

  PfxBox() = default;
  explicit PfxBox(const PfxVector3& halfExtent) : m_half(halfExtent) {}
  PfxBox(PfxFloat hx, PfxFloat hy, PfxFloat hz) : m_half(hx, hy, hz) {}
};

}  // namespace pfx
