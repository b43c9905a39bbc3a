// Checks the particle stages share: every particle valid, each rejection naming the
// particle and the value that is wrong.
#pragma once

#include "low_level/pfx_param_checks.h"
#include "pfx/base_level/particle/pfx_particle.h"

namespace pfx {

PfxInt32 pfxCheckParticles(const PfxParamNames& at, const PfxParticle* particles,
                           PfxUInt32 numParticles);

}  // namespace pfx
