// The row of a joint coupling: follower - multiplier * leader - offset held at zero. Its
// Jacobian is the follower axis' row minus multiplier times the leader axis' row, over the
// up to four bodies of the two joints, merged where the joints share a body (two fingers on
// one palm).
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>

#include "pfx/base_level/joint/pfx_joint_coupling.h"
#include "pfx/base_level/rigidbody/pfx_rigid_state.h"
#include "pfx/base_level/solver/pfx_solver_body.h"
#include "low_level/solver/pfx_joint_row.h"

namespace pfx {

namespace coupling_detail {

inline PfxFloat wrapAngle(PfxFloat angle) {
  return std::remainder(angle, 2 * PFX_PI);
}

inline void addToBody(PfxJointCoupling& coupling, PfxUInt32 rigidBodyId,
                      const PfxVector3& linear, const PfxVector3& angular) {
  for (PfxUInt32 i = 0; i < coupling.m_numBodies; ++i) {
    PfxJointCouplingBody& body = coupling.m_bodies[i];
    if (body.m_rigidBodyId != rigidBodyId) continue;
    body.m_linear += linear;
    body.m_angular += angular;
    return;
  }
  PfxJointCouplingBody& body = coupling.m_bodies[coupling.m_numBodies++];
  body.m_rigidBodyId = rigidBodyId;
  body.m_linear = linear;
  body.m_angular = angular;
}

// Adds `scale` times the rate of change of one joint coordinate to the coupling's
// Jacobian, and returns the coordinate. A translation is B's anchor along A's frame axis,
// which turns with A: that turning is part of its rate, (w_A x e) . d = w_A . (e x d). A
// rotation changes at the relative angular velocity along the direction the joint's own row
// uses (set up just before), except a swing-twist joint's cone row, which bounds the
// swing's size rather than swing1 itself.
inline PfxFloat addJointAxis(PfxJointCoupling& coupling, const PfxJoint& joint, PfxUInt32 axis,
                             PfxFloat scale, const PfxRigidState& stateA,
                             const PfxRigidState& stateB) {
  const PfxMatrix3 frameA = stateA.getOrientation().toRotationMatrix() * joint.m_frameA;
  PfxFloat coordinates[6];
  pfxCalcJointCoordinates(joint, stateA, stateB, coordinates);
  PfxVector3 linearA = PfxVector3::Zero(), angularA, linearB = PfxVector3::Zero(), angularB;
  if (axis < 3) {
    const PfxVector3 direction = frameA.col(axis);
    const PfxVector3 armA = stateA.getOrientation() * joint.m_anchorA;
    const PfxVector3 armB = stateB.getOrientation() * joint.m_anchorB;
    const PfxVector3 offset = stateB.getPosition() + armB - stateA.getPosition() - armA;
    linearA = -direction;
    linearB = direction;
    angularA = direction.cross(offset) - armA.cross(direction);
    angularB = armB.cross(direction);
  } else {
    const bool cone = joint.m_type == kPfxJointSwingTwist && axis == kPfxJointAxisSwing1;
    const PfxVector3 direction = cone ? PfxVector3(frameA.col(1)) : joint.m_axes[axis];
    angularA = -direction;
    angularB = direction;
  }
  addToBody(coupling, joint.m_rigidBodyIdA, scale * linearA, scale * angularA);
  addToBody(coupling, joint.m_rigidBodyIdB, scale * linearB, scale * angularB);
  return coordinates[axis];
}

}  // namespace coupling_detail

// The row's velocity from the chosen velocities of the solver bodies.
inline PfxFloat pfxJointCouplingVelocity(const PfxJointCoupling& coupling,
                                         const PfxSolverBody* solverBodies,
                                         PfxVector3 PfxSolverBody::*linear,
                                         PfxVector3 PfxSolverBody::*angular) {
  PfxFloat velocity = 0;
  for (PfxUInt32 i = 0; i < coupling.m_numBodies; ++i) {
    const PfxJointCouplingBody& body = coupling.m_bodies[i];
    const PfxSolverBody& sb = solverBodies[body.m_rigidBodyId];
    velocity += body.m_linear.dot(sb.*linear) + body.m_angular.dot(sb.*angular);
  }
  return velocity;
}

// Adds M^-1 J^T impulse to the chosen velocities.
inline void pfxApplyJointCouplingImpulse(const PfxJointCoupling& coupling, PfxFloat impulse,
                                         PfxSolverBody* solverBodies,
                                         PfxVector3 PfxSolverBody::*linear,
                                         PfxVector3 PfxSolverBody::*angular) {
  for (PfxUInt32 i = 0; i < coupling.m_numBodies; ++i) {
    const PfxJointCouplingBody& body = coupling.m_bodies[i];
    PfxSolverBody& sb = solverBodies[body.m_rigidBodyId];
    sb.*linear += (sb.m_massInv * impulse) * body.m_linear;
    sb.*angular += sb.m_inertiaInv * (impulse * body.m_angular);
  }
}

// Measures the coupling at the bodies' current states and sets up its row: a velocity row
// that keeps the error from changing, and a split impulse that removes bias * error. The
// coordinates of rotations are followed across turns (m_leaderPosition and
// m_followerPosition), so that a continuous joint winding past pi keeps its ratio.
inline void pfxSetupJointCouplingRow(PfxJointCoupling& coupling, const PfxJoint* joints,
                                     const PfxRigidState* states,
                                     const PfxSolverBody* solverBodies, PfxFloat timeStep,
                                     PfxFloat warmStartFactor) {
  const PfxJoint& leader = joints[coupling.m_leaderJointId];
  const PfxJoint& follower = joints[coupling.m_followerJointId];
  coupling.m_numBodies = 0;
  const PfxFloat followerRaw = coupling_detail::addJointAxis(
      coupling, follower, coupling.m_followerAxis, 1, states[follower.m_rigidBodyIdA],
      states[follower.m_rigidBodyIdB]);
  const PfxFloat leaderRaw = coupling_detail::addJointAxis(
      coupling, leader, coupling.m_leaderAxis, -coupling.m_multiplier,
      states[leader.m_rigidBodyIdA], states[leader.m_rigidBodyIdB]);
  auto follow = [](PfxFloat& tracked, PfxFloat raw, bool rotation) {
    tracked = rotation ? tracked + coupling_detail::wrapAngle(raw - tracked) : raw;
  };
  follow(coupling.m_leaderPosition, leaderRaw, coupling.m_leaderAxis >= 3);
  follow(coupling.m_followerPosition, followerRaw, coupling.m_followerAxis >= 3);
  coupling.m_error = coupling.m_followerPosition -
                     coupling.m_multiplier * coupling.m_leaderPosition - coupling.m_offset;

  PfxFloat k = 0;
  PfxFloat velocity = 0;
  for (PfxUInt32 i = 0; i < coupling.m_numBodies; ++i) {
    const PfxJointCouplingBody& body = coupling.m_bodies[i];
    const PfxSolverBody& sb = solverBodies[body.m_rigidBodyId];
    const PfxRigidState& state = states[body.m_rigidBodyId];
    k += sb.m_massInv * body.m_linear.squaredNorm() +
         body.m_angular.dot(sb.m_inertiaInv * body.m_angular);
    velocity += body.m_linear.dot(state.getLinearVelocity()) +
                body.m_angular.dot(state.getAngularVelocity());
  }
  const PfxFloat bound = coupling.m_maxImpulseForce > 0
                             ? coupling.m_maxImpulseForce * timeStep
                             : std::numeric_limits<PfxFloat>::max();
  PfxConstraintRow& row = coupling.m_row;
  row.m_normal.setZero();
  row.m_jacDiagInv = k > 0 ? PfxFloat(1) / k : PfxFloat(0);
  row.m_rhs = -velocity * row.m_jacDiagInv;
  row.m_lowerLimit = -bound;
  row.m_upperLimit = bound;
  row.m_accumImpulse = std::clamp(row.m_accumImpulse * warmStartFactor, -bound, bound);
  coupling.m_pushRhs = -coupling.m_bias * coupling.m_error / timeStep * row.m_jacDiagInv;
  coupling.m_pushImpulse = 0;
}

// One Gauss-Seidel update of the velocity row, or of the split impulse (push).
inline void pfxSolveJointCouplingRow(PfxJointCoupling& coupling, PfxSolverBody* solverBodies,
                                     bool push) {
  PfxVector3 PfxSolverBody::*linear =
      push ? &PfxSolverBody::m_pushLinearVelocity : &PfxSolverBody::m_deltaLinearVelocity;
  PfxVector3 PfxSolverBody::*angular =
      push ? &PfxSolverBody::m_pushAngularVelocity : &PfxSolverBody::m_deltaAngularVelocity;
  PfxConstraintRow& row = coupling.m_row;
  PfxFloat& accumulated = push ? coupling.m_pushImpulse : row.m_accumImpulse;
  const PfxFloat rhs = push ? coupling.m_pushRhs : row.m_rhs;
  const PfxFloat velocity = pfxJointCouplingVelocity(coupling, solverBodies, linear, angular);
  const PfxFloat previous = accumulated;
  accumulated =
      std::clamp(previous + rhs - row.m_jacDiagInv * velocity, row.m_lowerLimit, row.m_upperLimit);
  pfxApplyJointCouplingImpulse(coupling, accumulated - previous, solverBodies, linear, angular);
}

// Sweeps of the coupling together with the rows on its two axes, per solver iteration.
constexpr int kPfxJointCouplingSweeps = 4;

// The coupling and the limit and drive rows of its two axes, solved together by a few
// Gauss-Seidel sweeps: a drive on one axis acts through the coupling on both, and a limit
// on either holds both. Solved once each per iteration, a drive that meets a limit through
// the coupling passes one impulse per iteration around the loop, and the pair lags or
// overshoots for many steps. The joint rows here move every body that impulses move (a
// one-way body is not singled out, as it is for the joint's own pair).
inline void pfxSolveJointCouplingBlock(PfxJointCoupling& coupling, PfxJoint* joints,
                                       PfxSolverBody* solverBodies, bool push) {
  if (coupling.m_numBodies == 0) return;
  struct Side {
    PfxUInt32 jointId;
    PfxUInt32 axis;
  };
  const Side sides[2] = {{coupling.m_leaderJointId, coupling.m_leaderAxis},
                         {coupling.m_followerJointId, coupling.m_followerAxis}};
  // Bounded rows first, the coupling last: each sweep ends with the ratio exact, and a
  // drive gives way to it and to the limits.
  for (int sweep = 0; sweep < kPfxJointCouplingSweeps; ++sweep) {
    for (const bool drives : {true, false}) {
      for (const Side& side : sides) {
        PfxJoint& joint = joints[side.jointId];
        PfxJointConstraint& c = joint.m_constraints[side.axis];
        PfxSolverBody& a = solverBodies[joint.m_rigidBodyIdA];
        PfxSolverBody& b = solverBodies[joint.m_rigidBodyIdB];
        if (drives) {
          if (!push && c.m_driveRowUsed) {
            pfxSolveJointRow(c.m_driveRow, joint, side.axis, a, 1, b, 1);
          }
        } else if (push) {
          if (c.m_rowType != kPfxJointRowNone && (c.m_pushRhs != 0 || c.m_pushImpulse != 0)) {
            pfxSolveJointPushRow(c, joint, side.axis, a, 1, b, 1);
          }
        } else if (c.m_rowType != kPfxJointRowNone) {
          pfxSolveJointRow(c.m_constraintRow, joint, side.axis, a, 1, b, 1);
        }
      }
    }
    pfxSolveJointCouplingRow(coupling, solverBodies, push);
  }
}

}  // namespace pfx
