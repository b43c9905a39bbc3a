// A coupling between the coordinates of two joint axes: follower = multiplier * leader +
// offset (URDF <mimic>: gripper fingers, linkages). Solved as one more constraint row with
// the joints and contacts, over the up to four bodies of the two joints; its position
// error is removed with the joints' after the bodies have moved, so it does not drift.
#pragma once

#include "pfx/base_level/joint/pfx_joint.h"

namespace pfx {

// The share of one body in the coupling row: the row's velocity is the sum over its bodies
// of linear . v + angular . w. A body that both joints act on has one entry.
struct PfxJointCouplingBody {
  PfxVector3 m_linear;
  PfxVector3 m_angular;
  PfxUInt32 m_rigidBodyId;
};

constexpr PfxUInt32 PFX_JOINT_COUPLING_MAX_BODIES = 4;

struct PfxJointCoupling {
  PfxUInt32 m_leaderJointId;
  PfxUInt32 m_followerJointId;
  PfxUInt8 m_leaderAxis;    // 0..5, an axis of the leader joint that is free or limited
  PfxUInt8 m_followerAxis;  // 0..5, likewise on the follower
  PfxUInt8 m_active;
  PfxUInt8 m_numBodies;     // solver state: entries of m_bodies in use
  PfxFloat m_multiplier;
  PfxFloat m_offset;        // m or rad
  PfxFloat m_bias;          // fraction of the error corrected per step (0..1)
  PfxFloat m_maxImpulseForce;  // largest force or torque the coupling applies; <= 0: none

  // The two coordinates when last measured, rotations followed across turns (a continuous
  // joint past pi keeps counting): set them to the current coordinates
  // (pfxCalcJointCoordinates) before the first step; PfxWorld does.
  PfxFloat m_leaderPosition;
  PfxFloat m_followerPosition;

  // Solver state, set up each sub-step: the row (its impulse persists for warm starting),
  // its Jacobian, the split impulse that removes the position error, and that error,
  // follower - multiplier * leader - offset (m or rad) when last measured.
  PfxConstraintRow m_row;
  PfxJointCouplingBody m_bodies[PFX_JOINT_COUPLING_MAX_BODIES];
  PfxFloat m_pushRhs;
  PfxFloat m_pushImpulse;
  PfxFloat m_error;

  // Active, multiplier 1, offset 0, bias 1, no force limit, joints and axes 0.
  void reset();
};

// Checks a coupling against the joints it names: ids below numJoints, axes 0..5, neither
// axis locked, leader and follower not the same axis of the same joint, a multiplier, an
// offset, tracked positions and the error they make whose squares are finite, bias in
// [0, 1], a finite force limit. PFX_OK or the error code.
PfxInt32 pfxCheckJointCoupling(const PfxJointCoupling& coupling, const PfxJoint* joints,
                               PfxUInt32 numJoints);

}  // namespace pfx
