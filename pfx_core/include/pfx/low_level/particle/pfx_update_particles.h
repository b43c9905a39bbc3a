// Stage: the last of a particle sub-step. A particle's velocity becomes the distance it
// travelled over the sub-step divided by its length, constraint and contact corrections
// included, which is what makes position based dynamics unconditionally stable.
#pragma once

#include "pfx/base_level/particle/pfx_particle.h"
#include "pfx/base_level/task/pfx_task_manager.h"

namespace pfx {

struct PfxUpdateParticlesParam {
  PfxParticle* particles = nullptr;
  PfxUInt32 numParticles = 0;
  PfxFloat timeStep = PfxFloat(1) / 60;  // of the sub-step (s)
};

// Rejects a null particle array with particles and a time step that is not positive and
// finite (PFX_ERR_INVALID_VALUE); nothing changes then. Allocates nothing.
PfxInt32 pfxUpdateParticles(const PfxUpdateParticlesParam& param,
                            PfxTaskManager* taskManager = nullptr);

}  // namespace pfx
