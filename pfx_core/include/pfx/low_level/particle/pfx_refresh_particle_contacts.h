// Stage: at the start of each particle sub-step, after pfxIntegrateParticles, turns each
// contact plane between a particle and a convex shape (sphere, capsule, cylinder, box,
// convex mesh) to the closest point of the shape from where the particle is predicted to be.
// A plane found once per step is right for flat faces, but a particle sliding over a sphere
// or a capsule during the step would sink below the plane's tangent point. Contacts with a
// large mesh keep their triangle's plane, which is exact.
#pragma once

#include "pfx/base_level/collision/pfx_collidable.h"
#include "pfx/base_level/particle/pfx_particle.h"
#include "pfx/base_level/rigidbody/pfx_rigid_state.h"
#include "pfx/base_level/task/pfx_task_manager.h"

namespace pfx {

struct PfxRefreshParticleContactsParam {
  const PfxParticle* particles = nullptr;
  PfxUInt32 numParticles = 0;
  PfxParticleContact* contacts = nullptr;
  PfxUInt32 numContacts = 0;
  // Indexed by rigid body id.
  const PfxRigidState* offsetRigidStates = nullptr;
  const PfxCollidable* offsetCollidables = nullptr;
  PfxUInt32 numRigidBodies = 0;
};

// Rejects null arrays with a count (PFX_ERR_NULL_POINTER) and a contact naming a particle,
// body or shape that does not exist (PFX_ERR_OUT_OF_RANGE); nothing changes then.
// Allocates nothing.
PfxInt32 pfxRefreshParticleContacts(const PfxRefreshParticleContactsParam& param,
                                    PfxTaskManager* taskManager = nullptr);

}  // namespace pfx
