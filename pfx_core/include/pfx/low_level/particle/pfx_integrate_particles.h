// Stage: the first of a particle sub-step. Each particle that has a mass keeps its position
// as the sub-step's start, gains the velocity of gravity and damping, and moves on to where
// that velocity takes it; the constraint solve (pfx_solve_particle_constraints.h) then
// corrects these predicted positions, and pfxUpdateParticles derives the velocity from
// where the particle ends up.
#pragma once

#include "pfx/base_level/particle/pfx_particle.h"
#include "pfx/base_level/task/pfx_task_manager.h"

namespace pfx {

struct PfxIntegrateParticlesParam {
  PfxParticle* particles = nullptr;
  PfxUInt32 numParticles = 0;
  PfxVector3 gravity = PfxVector3(0, PfxFloat(-9.80665), 0);
  // Fraction of the velocity lost per second (1/s; air drag on cloth and hair), applied as
  // v / (1 + linearDamping * timeStep) so that it never reverses the velocity, and before
  // gravity, so that it slows motion without lightening what hangs at rest.
  PfxFloat linearDamping = 0;
  PfxFloat timeStep = PfxFloat(1) / 60;  // of the sub-step (s)
};

// Rejects a null particle array with particles, a time step that is not positive and
// finite, non-finite gravity, a negative or non-finite damping (PFX_ERR_INVALID_VALUE)
// and any particle that pfxIsValidParticle rejects (PFX_ERR_INVALID_VALUE, naming it);
// nothing moves then. Allocates nothing.
PfxInt32 pfxIntegrateParticles(const PfxIntegrateParticlesParam& param,
                               PfxTaskManager* taskManager = nullptr);

}  // namespace pfx
