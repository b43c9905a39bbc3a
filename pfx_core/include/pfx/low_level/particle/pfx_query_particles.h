// Rays and contact queries against particles. A particle is a sphere of its radius; a cloth
// (particles with triangles) is seen as its surface: the triangles through the particles'
// centres, hit from either side as a large mesh is, which is what a range sensor sees of a
// thin sheet. Rays follow the rules of rays against bodies (pfx_ray.h): the filters of
// particle and ray must match (for a triangle, those of its three particles), and a ray
// starting inside a particle does not hit it.
#pragma once

#include "pfx/base_level/particle/pfx_particle.h"
#include "pfx/base_level/raycast/pfx_ray.h"
#include "pfx/low_level/collision/pfx_query_contacts.h"

namespace pfx {

// Keeps in `out` the closest hit nearer than out.m_variable, among the triangles when
// numTriangles > 0 (triples of indices into particles, as PfxParticleGroupDesc holds them)
// and among the particles' spheres otherwise; call it again with more particles to keep the
// closest over several groups. A hit writes the point, the unit normal (out of the sphere,
// or the triangle's turned against the ray), the fraction, the particle (for a triangle, its
// corner nearest the hit), m_triangleIndex (PFX_RAY_NO_TRIANGLE for a sphere), m_objectId
// PFX_RAY_NO_OBJECT and m_contactFlag; m_particleGroupId is the caller's. Rejects what
// pfxCheckRayInput rejects, null arrays with particles or triangles, and a triangle index
// not below numParticles (PFX_ERR_OUT_OF_RANGE); out is untouched then. The tests run in
// double whatever PfxFloat is.
PfxInt32 pfxCastParticleRay(const PfxRayInput& ray, const PfxParticle* particles,
                            PfxUInt32 numParticles, const PfxUInt32* triangleIndices,
                            PfxUInt32 numTriangles, PfxRayOutput& out);

// PfxParticleQueryContact::m_particleGroupId until PfxWorld fills it in.
constexpr PfxUInt32 PFX_PARTICLE_NONE = 0xffffffffu;

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
