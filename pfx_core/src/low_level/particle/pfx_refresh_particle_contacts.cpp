#include "pfx/low_level/particle/pfx_refresh_particle_contacts.h"

#include "base_level/collision/pfx_contact_checked.h"
#include "low_level/pfx_param_checks.h"
#include "pfx/base_level/collision/pfx_contact_shapes.h"

namespace pfx {

namespace {

constexpr PfxUInt32 kContactsPerTask = 256;

// The body shape of the contacts refreshed last, placed and checked once: a cloth's
// contacts come particle by particle, most of them with the same shape of the same body,
// whose pose stays put through the refresh.
struct RefreshedBodyShape {
  PfxUInt32 body = ~0u;
  PfxUInt8 shapeId = 0;
  const PfxShape* shape = nullptr;
  PfxTransform3 pose;
  PfxQuat toBody;
  PfxVector3 bodyPosition;
  bool usable = false;  // convex, valid and at a rigid pose: else no contact is found

  void placeFor(const PfxParticleContact& c, const PfxRefreshParticleContactsParam& param) {
    if (c.m_other == body && c.m_shapeId == shapeId && shape) return;
    body = c.m_other;
    shapeId = c.m_shapeId;
    shape = &param.offsetCollidables[body].getShape(shapeId);
    const PfxRigidState& state = param.offsetRigidStates[body];
    pose = state.getTransform() * shape->getOffsetTransform();
    toBody = state.getOrientation().conjugate();
    bodyPosition = state.getPosition();
    usable = pfxIsContactShape(*shape) && pfxIsRigidTransform(pose);
  }
};

void refresh(PfxParticleContact& c, const PfxRefreshParticleContactsParam& param,
             RefreshedBodyShape& at) {
  if (param.offsetCollidables[c.m_other].getShape(c.m_shapeId).getType() ==
      kPfxShapeLargeTriMesh) {
    return;
  }
  at.placeFor(c, param);
  const PfxParticle& p = param.particles[c.m_particle];
  PfxShape sphere;
  sphere.reset();
  sphere.setSphere(PfxSphere(p.m_radius));
  // Far enough to find the closest point wherever the particle went within the sub-step.
  const PfxFloat threshold = 4 * p.m_radius + (p.m_position - p.m_previousPosition).norm();
  PfxContactCandidate closest[PFX_MAX_CONTACT_CANDIDATES];
  const PfxUInt32 found =
      at.usable && pfxIsFinite(threshold) && pfxIsFinite(p.m_position) &&
              pfxIsContactShape(sphere)
          ? pfxContactCheckedConvexShapes(sphere, pfxMakeTransform(PfxQuat::Identity(), p.m_position),
                                          *at.shape, at.pose, threshold, closest,
                                          PFX_MAX_CONTACT_CANDIDATES)
          : 0;
  if (found == 0) {
    // Out of reach for this sub-step: the contact rests (a zero normal), rather than holding
    // the particle to a plane that no longer touches it.
    c.m_localNormal.setZero();
    return;
  }
  c.m_localPoint = at.toBody * (closest[0].m_pointB - at.bodyPosition);
  c.m_localNormal = at.toBody * (-closest[0].m_normal);
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
                          RefreshedBodyShape last;
                          for (PfxUInt32 i = begin; i < end; ++i) {
                            PfxParticleContact& c = param.contacts[i];
                            if (c.m_kind == kPfxParticleContactRigidBody) refresh(c, param, last);
                          }
                        });
}

}  // namespace pfx
