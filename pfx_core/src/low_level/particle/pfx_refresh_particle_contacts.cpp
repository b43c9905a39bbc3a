#include "pfx/low_level/particle/pfx_refresh_particle_contacts.h"

#include "low_level/pfx_param_checks.h"
#include "pfx/base_level/collision/pfx_contact_shapes.h"

namespace pfx {

namespace {

constexpr PfxUInt32 kContactsPerTask = 256;

void refresh(PfxParticleContact& c, const PfxRefreshParticleContactsParam& param) {
  const PfxShape& shape = param.offsetCollidables[c.m_other].getShape(c.m_shapeId);
  if (shape.getType() == kPfxShapeLargeTriMesh) return;
  const PfxParticle& p = param.particles[c.m_particle];
  const PfxRigidState& state = param.offsetRigidStates[c.m_other];
  PfxShape sphere;
  sphere.reset();
  sphere.setSphere(PfxSphere(p.m_radius));
  const PfxTransform3 bodyTransform = state.getTransform();
  // Far enough to find the closest point wherever the particle went within the sub-step.
  const PfxFloat threshold = 4 * p.m_radius + (p.m_position - p.m_previousPosition).norm();
  PfxContactCandidate closest[PFX_MAX_CONTACT_CANDIDATES];
  const PfxUInt32 found = pfxContactConvexShapes(
      sphere, pfxMakeTransform(PfxQuat::Identity(), p.m_position), shape,
      bodyTransform * shape.getOffsetTransform(), threshold, closest, PFX_MAX_CONTACT_CANDIDATES);
  if (found == 0) {
    // Out of reach for this sub-step: the contact rests (a zero normal), rather than holding
    // the particle to a plane that no longer touches it.
    c.m_localNormal.setZero();
    return;
  }
  const PfxQuat toBody = state.getOrientation().conjugate();
  c.m_localPoint = toBody * (closest[0].m_pointB - state.getPosition());
  c.m_localNormal = toBody * (-closest[0].m_normal);
}

}  // namespace

PfxInt32 pfxRefreshParticleContacts(const PfxRefreshParticleContactsParam& param,
                                    PfxTaskManager* taskManager) {
  const PfxParamNames at{"pfxRefreshParticleContacts", "PfxRefreshParticleContactsParam"};
  PfxInt32 err = PFX_OK;
  if ((err = pfxCheckRequired(at, {{param.contacts, "contacts"}, {param.particles, "particles"}},
                              "numContacts", param.numContacts)) != PFX_OK) {
    return err;
  }
  for (PfxUInt32 i = 0; i < param.numContacts; ++i) {
    const PfxParticleContact& c = param.contacts[i];
    if (c.m_particle >= param.numParticles) {
      return pfxRejectParam(PFX_ERR_OUT_OF_RANGE,
                            "pfxRefreshParticleContacts: contacts[%u].particle is %u, but "
                            "numParticles is %u",
                            i, c.m_particle, param.numParticles);
    }
    if (c.m_kind != kPfxParticleContactRigidBody) continue;
    if (c.m_other >= param.numRigidBodies || !param.offsetRigidStates ||
        !param.offsetCollidables) {
      return pfxRejectParam(PFX_ERR_OUT_OF_RANGE,
                            "pfxRefreshParticleContacts: contacts[%u] names rigid body %u, but "
                            "numRigidBodies is %u (or the body arrays are null)",
                            i, c.m_other, param.numRigidBodies);
    }
    if (c.m_shapeId >= param.offsetCollidables[c.m_other].getNumShapes()) {
      return pfxRejectParam(PFX_ERR_OUT_OF_RANGE,
                            "pfxRefreshParticleContacts: contacts[%u] names shape %u of rigid "
                            "body %u, which has %u",
                            i, unsigned(c.m_shapeId), c.m_other,
                            unsigned(param.offsetCollidables[c.m_other].getNumShapes()));
    }
  }
  return pfxParallelFor(taskManager, param.numContacts, kContactsPerTask,
                        [&](PfxUInt32 begin, PfxUInt32 end) {
                          for (PfxUInt32 i = begin; i < end; ++i) {
                            PfxParticleContact& c = param.contacts[i];
                            if (c.m_kind == kPfxParticleContactRigidBody) refresh(c, param);
                          }
                        });
}

}  // namespace pfx
