#include "pfx/low_level/particle/pfx_query_particles.h"

#include <cmath>

#include "low_level/pfx_param_checks.h"
#include "pfx/base_level/collision/pfx_collidable.h"
#include "pfx/base_level/collision/pfx_contact_shapes.h"

namespace pfx {

PfxInt32 pfxCastParticleRay(const PfxRayInput& ray, const PfxParticle* particles,
                            PfxUInt32 numParticles, PfxParticleRayOutput& out) {
  if (const PfxInt32 err = pfxCheckRayInput(ray); err != PFX_OK) {
    return pfxRejectParam(err, "pfxCastParticleRay: the ray's start or direction is not finite, "
                               "or its length is zero");
  }
  const PfxParamNames at{"pfxCastParticleRay", ""};
  if (const PfxInt32 err =
          pfxCheckRequired(at, {{particles, "particles"}}, "numParticles", numParticles);
      err != PFX_OK) {
    return err;
  }
  const PfxVector3& start = ray.m_startPosition;
  const PfxVector3& dir = ray.m_direction;
  const PfxFloat a = dir.squaredNorm();
  for (PfxUInt32 i = 0; i < numParticles; ++i) {
    const PfxParticle& p = particles[i];
    if (!pfxContactFiltersMatch(ray.m_contactFilterSelf, ray.m_contactFilterTarget,
                                p.m_contactFilterSelf, p.m_contactFilterTarget)) {
      continue;
    }
    // |start + t dir - centre| = radius, the smaller root, for a ray from outside.
    const PfxVector3 m = start - p.m_position;
    const PfxFloat c = m.squaredNorm() - p.m_radius * p.m_radius;
    if (c <= 0) continue;
    const PfxFloat b = m.dot(dir);
    if (b >= 0) continue;
    const PfxFloat discriminant = b * b - a * c;
    if (discriminant < 0) continue;
    const PfxFloat t = (-b - std::sqrt(discriminant)) / a;
    if (t < 0 || t >= out.m_variable) continue;
    out.m_variable = t;
    out.m_contactPoint = start + t * dir;
    out.m_contactNormal = (out.m_contactPoint - p.m_position).normalized();
    out.m_particle = i;
    out.m_contactFlag = true;
  }
  return PFX_OK;
}

PfxInt32 pfxQueryParticleContacts(const PfxContactQueryInput& query, const PfxParticle* particles,
                                  PfxUInt32 numParticles, PfxParticleQueryContact* out,
                                  PfxUInt32 maxContacts, PfxQueryContactsResult& result) {
  // The query itself is checked as pfxQueryContacts checks it, against no bodies.
  PfxQueryContactsResult none;
  if (const PfxInt32 err = pfxQueryContacts(query, PfxQueryContactsParam(), nullptr, 0, none);
      err != PFX_OK) {
    return err;
  }
  const PfxParamNames at{"pfxQueryParticleContacts", ""};
  if (const PfxInt32 err =
          pfxCheckRequired(at, {{particles, "particles"}}, "numParticles", numParticles);
      err != PFX_OK) {
    return err;
  }
  if (!out && maxContacts > result.numContacts) {
    return pfxRejectNull(at, "out", "maxContacts", maxContacts);
  }
  PfxVector3 center, half;
  query.collidable->getWorldAabb(query.transform, center, half);
  half += PfxVector3::Constant(query.contactThreshold);
  for (PfxUInt32 i = 0; i < numParticles; ++i) {
    const PfxParticle& p = particles[i];
    if (!pfxContactFiltersMatch(query.contactFilterSelf, query.contactFilterTarget,
                                p.m_contactFilterSelf, p.m_contactFilterTarget) ||
        ((p.m_position - center).cwiseAbs() - half).maxCoeff() > p.m_radius) {
      continue;
    }
    PfxShape sphere;
    sphere.reset();
    sphere.setSphere(PfxSphere(p.m_radius));
    PfxCollidable particleCollidable;
    particleCollidable.reset();
    particleCollidable.addShape(sphere);
    particleCollidable.finish();
    PfxContactCandidate candidates[PFX_MAX_CONTACT_CANDIDATES];
    const PfxUInt32 count = pfxContactCollidables(
        *query.collidable, query.transform, particleCollidable,
        pfxMakeTransform(PfxQuat::Identity(), p.m_position), query.contactThreshold, candidates,
        PFX_MAX_CONTACT_CANDIDATES);
    for (PfxUInt32 k = 0; k < count; ++k) {
      if (result.numContacts == maxContacts) {
        result.truncated = true;
        return PFX_OK;
      }
      out[result.numContacts].m_contact = candidates[k];
      out[result.numContacts].m_particleGroupId = PFX_PARTICLE_NONE;
      out[result.numContacts].m_particle = i;
      ++result.numContacts;
    }
  }
  return PFX_OK;
}

}  // namespace pfx
