// Rays and contact queries against particles, each a sphere of its radius: what a sensor
// sees of a cloth, or what a gripper's fingers touch of a rope. Rays follow the rules of
// rays against bodies (pfx_ray.h): the filters of particle and ray must match, and a ray
// starting inside a particle does not hit it.
#pragma once

#include "pfx/base_level/particle/pfx_particle.h"
#include "pfx/base_level/raycast/pfx_ray.h"
#include "pfx/low_level/collision/pfx_query_contacts.h"

namespace pfx {

// PfxParticleRayOutput::m_particle on a miss.
constexpr PfxUInt32 PFX_PARTICLE_NONE = 0xffffffffu;

struct PfxParticleRayOutput {
  PfxVector3 m_contactPoint = PfxVector3::Zero();
  PfxVector3 m_contactNormal = PfxVector3::Zero();  // unit, out of the particle
  PfxFloat m_variable = 1;                           // fraction of the ray; 1 on a miss
  PfxUInt32 m_particleGroupId = PFX_PARTICLE_NONE;   // filled in by PfxWorld
  PfxUInt32 m_particle = PFX_PARTICLE_NONE;
  bool m_contactFlag = false;
};

// The closest hit among particles[0..numParticles-1] nearer than out.m_variable: call it
// again with more particles to keep the closest over several arrays. Rejects what
// pfxCheckRayInput rejects and a null array with particles; out is untouched then.
PfxInt32 pfxCastParticleRay(const PfxRayInput& ray, const PfxParticle* particles,
                            PfxUInt32 numParticles, PfxParticleRayOutput& out);

// One point of a particle query: side A the queried collidable, side B the particle (a
// sphere shape), as in PfxQueryContact.
struct PfxParticleQueryContact {
  PfxContactCandidate m_contact;
  PfxUInt32 m_particleGroupId;  // filled in by PfxWorld
  PfxUInt32 m_particle;
};

// Appends to out[result.numContacts .. maxContacts-1] the particles within the query's
// threshold of its collidable (filters as for bodies), and sets result.truncated when some
// do not fit. Rejects what pfxQueryContacts rejects of the query and a null array with
// particles; nothing is written then.
PfxInt32 pfxQueryParticleContacts(const PfxContactQueryInput& query, const PfxParticle* particles,
                                  PfxUInt32 numParticles, PfxParticleQueryContact* out,
                                  PfxUInt32 maxContacts, PfxQueryContactsResult& result);

}  // namespace pfx
