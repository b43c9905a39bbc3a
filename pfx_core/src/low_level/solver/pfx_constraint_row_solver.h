// The arithmetic every solver row shares, contacts and joints alike: effective mass along
// a direction, and one projected Gauss-Seidel update of a row between two bodies.
// `receivesA`/`receivesB` are 0 or 1: a body facing a one-way body takes no impulse.
#pragma once

#include <algorithm>

#include "pfx/base_level/collision/pfx_contact_manifold.h"
#include "pfx/base_level/solver/pfx_constraint_row.h"
#include "pfx/base_level/rigidbody/pfx_rigid_state.h"
#include "pfx/base_level/solver/pfx_solver_body.h"

namespace pfx {

// 1 / (J M^-1 J^T) for a row that pushes B along `normal` at arm rB and A the opposite way
// at rA; 0 when neither body can move along it.
inline PfxFloat pfxCalcJacDiagInv(const PfxVector3& normal, const PfxSolverBody& a,
                                  const PfxVector3& rA, PfxFloat receivesA,
                                  const PfxSolverBody& b, const PfxVector3& rB,
                                  PfxFloat receivesB) {
  const PfxVector3 raXn = rA.cross(normal);
  const PfxVector3 rbXn = rB.cross(normal);
  const PfxFloat k = receivesA * (a.m_massInv + raXn.dot(a.m_inertiaInv * raXn)) +
                     receivesB * (b.m_massInv + rbXn.dot(b.m_inertiaInv * rbXn));
  return k > PfxFloat(0) ? PfxFloat(1) / k : PfxFloat(0);
}

// Velocity of B's point rB relative to A's point rA, from the bodies' velocity changes.
inline PfxVector3 pfxRelativeDeltaVelocity(const PfxSolverBody& a, const PfxVector3& rA,
                                           const PfxSolverBody& b, const PfxVector3& rB) {
  return b.m_deltaLinearVelocity + b.m_deltaAngularVelocity.cross(rB) - a.m_deltaLinearVelocity -
         a.m_deltaAngularVelocity.cross(rA);
}

// Adds to one body's chosen velocities what the generalized impulse (linear, and angular
// about its centre of mass) gives it.
inline void pfxApplyBodyImpulse(PfxSolverBody& body, const PfxVector3& linear,
                                const PfxVector3& angular,
                                PfxVector3 PfxSolverBody::*linearVelocity,
                                PfxVector3 PfxSolverBody::*angularVelocity) {
  body.*linearVelocity += body.m_massInv * linear;
  body.*angularVelocity += body.m_inertiaInv * angular;
}

// By default to the solved velocities; the split impulses pass the push velocities.
inline void pfxApplyRowImpulse(
    const PfxVector3& normal, PfxFloat impulse, PfxSolverBody& a, const PfxVector3& rA,
    PfxFloat receivesA, PfxSolverBody& b, const PfxVector3& rB, PfxFloat receivesB,
    PfxVector3 PfxSolverBody::*linearVelocity = &PfxSolverBody::m_deltaLinearVelocity,
    PfxVector3 PfxSolverBody::*angularVelocity = &PfxSolverBody::m_deltaAngularVelocity) {
  const PfxVector3 linear = normal * impulse;
  if (pfxTakesImpulse(a, receivesA)) {
    pfxApplyBodyImpulse(a, -linear, -rA.cross(linear), linearVelocity, angularVelocity);
  }
  if (pfxTakesImpulse(b, receivesB)) {
    pfxApplyBodyImpulse(b, linear, rB.cross(linear), linearVelocity, angularVelocity);
  }
}

// Relative normal velocity at a contact point, from the chosen velocities of the bodies
// (the solved changes or the push velocities).
inline PfxFloat pfxContactNormalVelocity(const PfxContactPoint& cp, const PfxSolverBody& a,
                                         const PfxSolverBody& b,
                                         PfxVector3 PfxSolverBody::*linear,
                                         PfxVector3 PfxSolverBody::*angular) {
  return cp.getNormal().dot(b.*linear + (b.*angular).cross(cp.m_armB) - a.*linear -
                            (a.*angular).cross(cp.m_armA));
}

// Applies normal impulses `delta` at a manifold's points to the chosen velocities.
inline void pfxApplyNormalImpulses(const PfxContactManifold& manifold, const PfxFloat* delta,
                                   PfxSolverBody& a, PfxFloat receivesA, PfxSolverBody& b,
                                   PfxFloat receivesB, PfxVector3 PfxSolverBody::*linear,
                                   PfxVector3 PfxSolverBody::*angular) {
  PfxVector3 force = PfxVector3::Zero();
  PfxVector3 torqueA = PfxVector3::Zero();
  PfxVector3 torqueB = PfxVector3::Zero();
  for (PfxUInt32 i = 0; i < manifold.getNumContacts(); ++i) {
    const PfxContactPoint& cp = manifold.getContactPoint(i);
    const PfxVector3 impulse = cp.getNormal() * delta[i];
    force += impulse;
    torqueA += cp.m_armA.cross(impulse);
    torqueB += cp.m_armB.cross(impulse);
  }
  if (pfxTakesImpulse(a, receivesA)) pfxApplyBodyImpulse(a, -force, -torqueA, linear, angular);
  if (pfxTakesImpulse(b, receivesB)) pfxApplyBodyImpulse(b, force, torqueB, linear, angular);
}

// One Gauss-Seidel update: the impulse that brings the row to its target velocity, with the
// accumulated impulse clamped to the row's limits.
inline void pfxSolveRow(PfxConstraintRow& row, PfxSolverBody& a, const PfxVector3& rA,
                        PfxFloat receivesA, PfxSolverBody& b, const PfxVector3& rB,
                        PfxFloat receivesB) {
  const PfxFloat relative = row.m_normal.dot(pfxRelativeDeltaVelocity(a, rA, b, rB));
  const PfxFloat previous = row.m_accumImpulse;
  row.m_accumImpulse = std::clamp(previous + row.m_rhs - row.m_jacDiagInv * relative,
                                  row.m_lowerLimit, row.m_upperLimit);
  pfxApplyRowImpulse(row.m_normal, row.m_accumImpulse - previous, a, rA, receivesA, b, rB,
                     receivesB);
}

// Moves a body by its push velocities over the step: the split impulses' position
// correction, which leaves the body's velocity alone. False when they are zero and the body
// stays where it was.
inline bool pfxApplyPush(PfxRigidState& state, const PfxSolverBody& body, PfxFloat timeStep) {
  if (body.m_pushLinearVelocity.isZero(0) && body.m_pushAngularVelocity.isZero(0)) return false;
  state.setPosition(state.getPosition() + body.m_pushLinearVelocity * timeStep);
  const PfxVector3 turn = body.m_pushAngularVelocity * timeStep;
  const PfxFloat angle = turn.norm();
  if (angle > 0) {
    const PfxQuat spin(Eigen::AngleAxis<PfxFloat>(angle, turn / angle));
    state.setOrientation((spin * state.getOrientation()).normalized());
  }
  return true;
}

}  // namespace pfx
