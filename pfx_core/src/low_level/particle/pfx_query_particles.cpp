#include "pfx/low_level/particle/pfx_query_particles.h"

#include <algorithm>
#include <cmath>

#include "low_level/pfx_param_checks.h"
#include "pfx/base_level/collision/pfx_collidable.h"
#include "pfx/base_level/collision/pfx_contact_shapes.h"
#include "pfx/base_level/raycast/pfx_ray_shapes.h"

namespace pfx {

namespace {

using Vec3d = Eigen::Matrix<double, 3, 1>;

bool rayMeetsParticle(const PfxRayInput& ray, const PfxParticle& p) {
  return pfxContactFiltersMatch(ray.m_contactFilterSelf, ray.m_contactFilterTarget,
                                p.m_contactFilterSelf, p.m_contactFilterTarget);
}

// The ray against triangle (a, b, c), both faces (Moller and Trumbore 1997), in double: on
// a hit at a fraction below `fraction`, writes it and the barycentric weights of b and c.
bool castTriangle(const Vec3d& start, const Vec3d& dir, const Vec3d& a, const Vec3d& b,
                  const Vec3d& c, double& fraction, double& u, double& v) {
  const Vec3d ab = b - a, ac = c - a;
  const Vec3d p = dir.cross(ac);
  const double det = ab.dot(p);
  if (det == 0) return false;  // the ray runs in the triangle's plane, or it is degenerate
  const double inverse = 1 / det;
  const Vec3d fromA = start - a;
  const double hitU = fromA.dot(p) * inverse;
  if (hitU < 0 || hitU > 1) return false;
  const Vec3d q = fromA.cross(ab);
  const double hitV = dir.dot(q) * inverse;
  if (hitV < 0 || hitU + hitV > 1) return false;
  const double t = ac.dot(q) * inverse;
  if (t < 0 || t >= fraction) return false;
  fraction = t;
  u = hitU;
  v = hitV;
  return true;
}

void keepHit(const PfxRayInput& ray, PfxFloat fraction, const PfxVector3& normal,
             PfxUInt32 particle, PfxUInt32 triangle, PfxRayOutput& out) {
  out.m_variable = fraction;
  out.m_contactPoint = ray.m_startPosition + fraction * ray.m_direction;
  out.m_contactNormal = normal;
  out.m_objectId = PFX_RAY_NO_OBJECT;
  out.m_triangleIndex = triangle;
  out.m_shapeId = 0;
  out.m_particleIndex = particle;
  out.m_contactFlag = true;
}

void castSpheres(const PfxRayInput& ray, const PfxParticle* particles, PfxUInt32 numParticles,
                 PfxRayOutput& out) {
  for (PfxUInt32 i = 0; i < numParticles; ++i) {
    const PfxParticle& p = particles[i];
    if (!rayMeetsParticle(ray, p)) continue;
    PfxFloat fraction = out.m_variable;
    PfxVector3 normal;
    // Strictly nearer only: a body or an earlier particle hit at the same fraction stays.
    if (pfxRayCastSphere(PfxSphere(p.m_radius), ray.m_startPosition - p.m_position,
                         ray.m_direction, fraction, normal) &&
        fraction < out.m_variable) {
      keepHit(ray, fraction, normal, i, PFX_RAY_NO_TRIANGLE, out);
    }
  }
}

void castTriangles(const PfxRayInput& ray, const PfxParticle* particles,
                   const PfxUInt32* triangleIndices, PfxUInt32 numTriangles, PfxRayOutput& out) {
  const Vec3d start = ray.m_startPosition.cast<double>();
  const Vec3d dir = ray.m_direction.cast<double>();
  for (PfxUInt32 t = 0; t < numTriangles; ++t) {
    const PfxUInt32* corner = triangleIndices + 3 * t;
    const PfxParticle& a = particles[corner[0]];
    const PfxParticle& b = particles[corner[1]];
    const PfxParticle& c = particles[corner[2]];
    if (!rayMeetsParticle(ray, a) || !rayMeetsParticle(ray, b) || !rayMeetsParticle(ray, c)) {
      continue;
    }
    const Vec3d pa = a.m_position.cast<double>();
    const Vec3d pb = b.m_position.cast<double>();
    const Vec3d pc = c.m_position.cast<double>();
    double fraction = out.m_variable, u = 0, v = 0;
    if (!castTriangle(start, dir, pa, pb, pc, fraction, u, v)) continue;
    if (PfxFloat(fraction) >= out.m_variable) continue;
    Vec3d normal = (pb - pa).cross(pc - pa).normalized();
    if (normal.dot(dir) > 0) normal = -normal;
    const double weights[3] = {1 - u - v, u, v};
    const int nearest = int(std::max_element(weights, weights + 3) - weights);
    keepHit(ray, PfxFloat(fraction), normal.cast<PfxFloat>(), corner[nearest], t, out);
  }
}

}  // namespace

PfxInt32 pfxCastParticleRay(const PfxRayInput& ray, const PfxParticle* particles,
                            PfxUInt32 numParticles, const PfxUInt32* triangleIndices,
                            PfxUInt32 numTriangles, PfxRayOutput& out) {
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
  if (const PfxInt32 err = pfxCheckRequired(at, {{triangleIndices, "triangleIndices"}},
                                            "numTriangles", numTriangles);
      err != PFX_OK) {
    return err;
  }
  for (PfxUInt32 i = 0; i < 3 * numTriangles; ++i) {
    if (triangleIndices[i] >= numParticles) {
      return pfxRejectParam(PFX_ERR_OUT_OF_RANGE,
                            "pfxCastParticleRay: triangleIndices[%u] is %u, but numParticles is %u",
                            i, triangleIndices[i], numParticles);
    }
  }
  if (numTriangles > 0) {
    castTriangles(ray, particles, triangleIndices, numTriangles, out);
  } else {
    castSpheres(ray, particles, numParticles, out);
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
