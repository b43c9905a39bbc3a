#include "pfx/low_level/particle/pfx_update_particles.h"

#include "low_level/particle/pfx_solve_particle_pair.h"
#include "low_level/pfx_param_checks.h"

namespace pfx {

namespace {
constexpr PfxUInt32 kUpdatedParticlesPerTask = 1024;
}  // namespace

PfxInt32 pfxUpdateParticles(const PfxUpdateParticlesParam& param, PfxTaskManager* taskManager) {
  const PfxParamNames at{"pfxUpdateParticles", "PfxUpdateParticlesParam"};
  PfxInt32 err = PFX_OK;
  if ((err = pfxCheckTimeStep(at, param.timeStep)) != PFX_OK ||
      (err = pfxCheckRequired(at, {{param.particles, "particles"}}, "numParticles",
                              param.numParticles)) != PFX_OK) {
    return err;
  }
  if ((err = pfxCheckRequired(at, {{param.contacts, "contacts"}}, "numContacts",
                              param.numContacts)) != PFX_OK) {
    return err;
  }
  for (PfxUInt32 i = 0; i < param.numContacts && !param.offsetRigidStates; ++i) {
    if (param.contacts[i].m_kind == kPfxParticleContactRigidBody) {
      return pfxRejectNull(at, "offsetRigidStates", "numContacts", param.numContacts);
    }
  }
  const PfxFloat inverseStep = 1 / param.timeStep;
  err = pfxParallelFor(taskManager, param.numParticles, kUpdatedParticlesPerTask,
                       [&](PfxUInt32 begin, PfxUInt32 end) {
                         for (PfxUInt32 i = begin; i < end; ++i) {
                           PfxParticle& p = param.particles[i];
                           p.m_velocity = (p.m_position - p.m_previousPosition) * inverseStep;
                         }
                       });
  if (err != PFX_OK) return err;
  // In contact order, serially: a particle may have several contacts.
  for (PfxUInt32 i = 0; i < param.numContacts; ++i) {
    const PfxParticleContact& c = param.contacts[i];
    if (c.m_lambdaNormal <= 0) continue;
    PfxParticle& a = param.particles[c.m_particle];
    if (c.m_kind == kPfxParticleContactRigidBody) {
      if (a.m_massInv == 0) continue;
      const PfxRigidState& s = param.offsetRigidStates[c.m_other];
      const PfxVector3 n = s.getOrientation() * c.m_localNormal;
      const PfxVector3 point = s.getPosition() + s.getOrientation() * c.m_localPoint;
      const PfxVector3 bodyVelocity =
          s.getLinearVelocity() + s.getAngularVelocity().cross(point - s.getPosition());
      const PfxFloat separating = (a.m_velocity - bodyVelocity).dot(n);
      if (separating > 0) a.m_velocity -= separating * n;
    } else {
      pfxRemoveParticlePairSeparation(a, param.particles[c.m_other]);
    }
  }
  return PFX_OK;
}

void pfxRemoveParticlePairSeparation(PfxParticle& a, PfxParticle& b) {
  const PfxFloat w = a.m_massInv + b.m_massInv;
  const PfxVector3 d = a.m_position - b.m_position;
  const PfxFloat length = d.norm();
  if (w == 0 || length == 0) return;
  const PfxVector3 n = d / length;
  const PfxFloat separating = (a.m_velocity - b.m_velocity).dot(n);
  if (separating <= 0) return;
  a.m_velocity -= (a.m_massInv / w) * separating * n;
  b.m_velocity += (b.m_massInv / w) * separating * n;
}

}  // namespace pfx
