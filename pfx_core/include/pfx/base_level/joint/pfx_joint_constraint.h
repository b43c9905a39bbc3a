// One axis of a joint (seed chapter 10, "Mechanism of a Joint Constraint"): locked, free or
// limited, with the seed's bias, weight and damping, and, beyond the seed, a drive (target
// velocity or position under a force limit, or a commanded effort) and friction, as robot
// joints need.
#pragma once

#include "pfx/base_level/solver/pfx_constraint_row.h"

namespace pfx {

enum PfxJointLock : PfxUInt8 {
  kPfxJointLockFree = 0,
  kPfxJointLockLocked,
  kPfxJointLockLimit,  // held between m_movableLowerLimit and m_movableUpperLimit
};

enum PfxJointDrive : PfxUInt8 {
  kPfxJointDriveNone = 0,
  kPfxJointDriveVelocity,  // m_driveTarget is a velocity (m/s or rad/s)
  kPfxJointDrivePosition,  // m_driveTarget is a position (m or rad)
  // m_driveTarget is a force (N) or torque (N m) along the axis, cut to +-m_driveMaxForce:
  // an actuator's commanded effort, applied to both bodies each sub-step
  // (pfxApplyJointEfforts) rather than solved as a row, so that damping, friction, limits
  // and whatever the joint carries answer it as they answer gravity.
  kPfxJointDriveEffort,
};

// Whether the drive is a solver row aiming at a target (a velocity or a position); an
// effort drive is a force and leaves the row to friction and damping.
inline bool pfxDriveHasTarget(PfxUInt8 drive) {
  return drive == kPfxJointDriveVelocity || drive == kPfxJointDrivePosition;
}

// What the lock row of an axis does in the current step (set up by the solver).
enum PfxJointRowType : PfxUInt8 {
  kPfxJointRowNone = 0,
  kPfxJointRowEquality,  // holds the coordinate at a value, both ways
  kPfxJointRowLimit,     // keeps the coordinate on one side of a limit
};

struct PfxJointConstraint {
  PfxUInt8 m_lock;
  PfxUInt8 m_drive;
  PfxUInt8 m_rowType;       // solver state: PfxJointRowType of m_constraintRow
  PfxUInt8 m_driveRowUsed;  // solver state: whether m_driveRow acts this step
  PfxFloat m_movableLowerLimit;
  PfxFloat m_movableUpperLimit;
  // Fraction of the position error corrected per step (0..1).
  PfxFloat m_bias;
  // Scales every impulse of this axis (0..1); below 1 the axis is soft.
  PfxFloat m_weight;
  // Fraction of the relative velocity along a free or limited axis removed per step (0..1).
  PfxFloat m_damping;
  // Largest friction force (N) or torque (N m) resisting motion along the axis.
  PfxFloat m_friction;
  PfxFloat m_driveTarget;
  // Largest force (N) or torque (N m) the drive may apply (an effort drive too).
  PfxFloat m_driveMaxForce;

  // Solver state, set up each step: the lock or limit row, and the row that drives, damps
  // and rubs. Their impulses persist for warm starting.
  PfxConstraintRow m_constraintRow;
  PfxConstraintRow m_driveRow;
  PfxFloat m_pushRhs;      // split impulse that corrects the position error, from rest
  PfxFloat m_pushImpulse;  // accumulated over the step
  PfxFloat m_position;     // current coordinate along the axis (m or rad)
  // Velocity of m_constraintRow and of m_driveRow per unit impulse once the joint's tree
  // has answered it (joints in the solver's direct-solved forest); 0 until measured in the
  // current solve.
  PfxFloat m_treeResponse[2];

  void reset();

  // The value a locked axis (0) or an axis with equal limits holds.
  PfxFloat getLockedValue() const { return m_lock == kPfxJointLockLocked ? 0 : m_movableLowerLimit; }
};

}  // namespace pfx
