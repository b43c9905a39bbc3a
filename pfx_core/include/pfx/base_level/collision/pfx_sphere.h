// A sphere, represented only by its radius.
#pragma once

#include "pfx/base_level/base/pfx_common.h"

namespace pfx {

struct PfxSphere {
  PfxFloat m_radius = 0;

  PfxSphere() = default;
  explicit PfxSphere(PfxFloat radius) : m_radius(radius) {}
};

}  // namespace pfx
