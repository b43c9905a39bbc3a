// Stage: the last of a particle sub-step. A particle's velocity becomes the distance it
// travelled over the sub-step divided by its length, constraint and contact corrections
// included. Then, as in the velocity pass of Müller et al. 2020, each contact that pushed
// this sub-step loses the separating velocity its push created: a push out of a body or
// another particle corrects a position, it is not a bounce (restitution 0). Without this, a
// contact fighting a stiff constraint (cloth bending over an edge) turns each sub-step's
// correction into speed, and more sub-steps would make it worse.
#pragma once

#include "pfx/base_level/particle/pfx_particle.h"
#include "pfx/base_level/rigidbody/pfx_rigid_state.h"
#include "pfx/base_level/task/pfx_task_manager.h"

namespace pfx {

struct PfxUpdateParticlesParam {
  PfxParticle* particles = nullptr;
  PfxUInt32 numParticles = 0;
  PfxFloat timeStep = PfxFloat(1) / 60;  // of the sub-step (s)
  // The contacts pfxSolveParticleConstraints just solved (their multipliers say which
  // pushed), and the bodies they name; none is fine.
  const PfxParticleContact* contacts = nullptr;
  PfxUInt32 numContacts = 0;
  const PfxRigidState* offsetRigidStates = nullptr;
};

// Rejects a null particle array with particles, null contacts with numContacts, null
// states with a rigid-body contact (PFX_ERR_NULL_POINTER) and a time step that is not
// positive and finite (PFX_ERR_INVALID_VALUE); nothing changes then. The contacts are
// trusted to name particles and bodies that exist (the solve stage checked them). Allocates
// nothing.
PfxInt32 pfxUpdateParticles(const PfxUpdateParticlesParam& param,
                            PfxTaskManager* taskManager = nullptr);

}  // namespace pfx
