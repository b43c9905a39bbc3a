// The Jacobian of one joint row and the arithmetic on it. A translation row pulls the two
// anchors along its direction (the anchors' arms give it a turning part); a rotation row
// turns the bodies about its direction.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>

#include "pfx/base_level/joint/pfx_joint.h"
#include "pfx/base_level/solver/pfx_solver_body.h"

namespace pfx {

// An axis's lock row as a setup makes it from the joint's coordinates (m_position, or the
// same six measured elsewhere): none (a free axis, or a turn limited to no less than a whole
// turn), equality, or the nearer limit as a one-sided row. `error` is how far the row is to
// move its coordinate back: an equality row's distance from the locked value, a limit row's
// gap inside its limit (negative past it). A swing-twist joint's first swing measures the
// cone (`cone`): the swing angle against the upper limit.
struct PfxLockRow {
  PfxJointRowType type;
  PfxFloat position;
  PfxFloat error;
  bool atLower;
  bool cone;
};

inline PfxLockRow pfxLockRow(const PfxJoint& joint, PfxUInt32 axis,
                             const PfxFloat positions[6]) {
  const PfxJointConstraint& c = joint.m_constraints[axis];
  PfxFloat position = positions[axis];
  PfxFloat lower = c.m_movableLowerLimit;
  const PfxFloat upper = c.m_movableUpperLimit;
  const bool cone = joint.m_type == kPfxJointSwingTwist && axis == kPfxJointAxisSwing1;
  if (cone) {
    const PfxFloat s1 = positions[kPfxJointAxisSwing1];
    const PfxFloat s2 = positions[kPfxJointAxisSwing2];
    position = std::sqrt(s1 * s1 + s2 * s2);
    lower = -std::numeric_limits<PfxFloat>::max();
  }
  const bool rotation = axis >= 3;
  if (c.m_lock == kPfxJointLockFree ||
      (c.m_lock == kPfxJointLockLimit && rotation && lower <= -PFX_PI && upper >= PFX_PI)) {
    return {kPfxJointRowNone, position, 0, false, cone};
  }
  if (c.m_lock == kPfxJointLockLocked || lower == upper) {
    return {kPfxJointRowEquality, position, position - c.getLockedValue(), false, cone};
  }
  const bool atLower = position - lower < upper - position;
  return {kPfxJointRowLimit, position, atLower ? position - lower : upper - position, atLower,
          cone};
}

// The velocity along the row that moves its coordinate back over the step, at the joint's
// bias, before the speed limit; 0 for a limit row within its limit.
inline PfxFloat pfxLockRowPushVelocity(const PfxJointConstraint& c, const PfxLockRow& row,
                                       PfxFloat timeStep) {
  if (row.type == kPfxJointRowEquality || (row.type == kPfxJointRowLimit && row.error < 0)) {
    return -c.m_bias * row.error / timeStep;
  }
  return 0;
}

struct PfxJointRowJacobian {
  PfxVector3 linearA, angularA, linearB, angularB;
};

inline PfxJointRowJacobian pfxJointRowJacobian(const PfxJoint& joint, PfxUInt32 axis,
                                               const PfxVector3& direction) {
  if (axis < 3) {
    return {-direction, -joint.m_armA.cross(direction), direction,
            joint.m_armB.cross(direction)};
  }
  return {PfxVector3::Zero(), -direction, PfxVector3::Zero(), direction};
}

inline PfxFloat pfxJointRowVelocity(const PfxJointRowJacobian& j, const PfxVector3& linearA,
                                    const PfxVector3& angularA, const PfxVector3& linearB,
                                    const PfxVector3& angularB) {
  return j.linearA.dot(linearA) + j.angularA.dot(angularA) + j.linearB.dot(linearB) +
         j.angularB.dot(angularB);
}

// 1 / (J M^-1 J^T), or 0 when neither body can move along the row.
inline PfxFloat pfxJointRowJacDiagInv(const PfxJointRowJacobian& j, const PfxSolverBody& a,
                                      PfxFloat receivesA, const PfxSolverBody& b,
                                      PfxFloat receivesB) {
  const PfxFloat k = receivesA * (a.m_massInv * j.linearA.squaredNorm() +
                                  j.angularA.dot(a.m_inertiaInv * j.angularA)) +
                     receivesB * (b.m_massInv * j.linearB.squaredNorm() +
                                  j.angularB.dot(b.m_inertiaInv * j.angularB));
  return k > PfxFloat(0) ? PfxFloat(1) / k : PfxFloat(0);
}

// Adds M^-1 J^T impulse to the chosen velocities (the solved or the push velocities).
inline void pfxApplyJointRowImpulse(const PfxJointRowJacobian& j, PfxFloat impulse,
                                    PfxSolverBody& a, PfxFloat receivesA, PfxSolverBody& b,
                                    PfxFloat receivesB, PfxVector3 PfxSolverBody::*linear,
                                    PfxVector3 PfxSolverBody::*angular) {
  if (pfxTakesImpulse(a, receivesA)) {
    a.*linear += (a.m_massInv * impulse) * j.linearA;
    a.*angular += impulse * (a.m_inertiaInv * j.angularA);
  }
  if (pfxTakesImpulse(b, receivesB)) {
    b.*linear += (b.m_massInv * impulse) * j.linearB;
    b.*angular += impulse * (b.m_inertiaInv * j.angularB);
  }
}

// One Gauss-Seidel update of a joint row (velocities) with its impulse clamped to the
// row's limits.
inline void pfxSolveJointRow(PfxConstraintRow& row, const PfxJoint& joint, PfxUInt32 axis,
                             PfxSolverBody& a, PfxFloat receivesA, PfxSolverBody& b,
                             PfxFloat receivesB) {
  const PfxJointRowJacobian j = pfxJointRowJacobian(joint, axis, row.m_normal);
  const PfxFloat velocity =
      pfxJointRowVelocity(j, a.m_deltaLinearVelocity, a.m_deltaAngularVelocity,
                          b.m_deltaLinearVelocity, b.m_deltaAngularVelocity);
  const PfxFloat previous = row.m_accumImpulse;
  row.m_accumImpulse = std::clamp(previous + row.m_rhs - row.m_jacDiagInv * velocity,
                                  row.m_lowerLimit, row.m_upperLimit);
  pfxApplyJointRowImpulse(j, row.m_accumImpulse - previous, a, receivesA, b, receivesB,
                          &PfxSolverBody::m_deltaLinearVelocity,
                          &PfxSolverBody::m_deltaAngularVelocity);
}

// The same for the split impulse of a lock row: unbounded for an equality, pushing only
// away from a limit.
inline void pfxSolveJointPushRow(PfxJointConstraint& c, const PfxJoint& joint, PfxUInt32 axis,
                                 PfxSolverBody& a, PfxFloat receivesA, PfxSolverBody& b,
                                 PfxFloat receivesB) {
  const PfxConstraintRow& row = c.m_constraintRow;
  const PfxJointRowJacobian j = pfxJointRowJacobian(joint, axis, row.m_normal);
  const PfxFloat velocity =
      pfxJointRowVelocity(j, a.m_pushLinearVelocity, a.m_pushAngularVelocity,
                          b.m_pushLinearVelocity, b.m_pushAngularVelocity);
  const PfxFloat previous = c.m_pushImpulse;
  c.m_pushImpulse = previous + c.m_pushRhs - row.m_jacDiagInv * velocity;
  if (c.m_rowType == kPfxJointRowLimit) c.m_pushImpulse = std::max(c.m_pushImpulse, PfxFloat(0));
  pfxApplyJointRowImpulse(j, c.m_pushImpulse - previous, a, receivesA, b, receivesB,
                          &PfxSolverBody::m_pushLinearVelocity,
                          &PfxSolverBody::m_pushAngularVelocity);
}

}  // namespace pfx
