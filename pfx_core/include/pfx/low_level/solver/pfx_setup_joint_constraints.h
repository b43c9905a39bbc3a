// Stage (4b'): joints become solver rows (seed chapter 4, "Set up Constraints").
#pragma once

#include "pfx/base_level/broadphase/pfx_broadphase_pair.h"
#include "pfx/base_level/joint/pfx_joint.h"
#include "pfx/base_level/joint/pfx_joint_coupling.h"
#include "pfx/base_level/rigidbody/pfx_rigid_body.h"
#include "pfx/base_level/solver/pfx_solver_body.h"
#include "pfx/base_level/task/pfx_task_manager.h"

namespace pfx {

struct PfxSetupJointConstraintsParam {
  PfxConstraintPair* jointPairs = nullptr;  // from pfxUpdateJointPairs
  PfxUInt32 numJointPairs = 0;
  PfxJoint* offsetJoints = nullptr;  // indexed by pfxGetConstraintId(pair)
  // To check the pairs' joint ids against; 0 (the seed gives none) checks nothing, and each
  // pair's id must index offsetJoints. Couplings need it: they name joints by id.
  PfxUInt32 numJoints = 0;
  // Couplings between the joints' coordinates, set up after the joints.
  PfxJointCoupling* offsetJointCouplings = nullptr;
  PfxUInt32 numJointCouplings = 0;
  const PfxRigidState* offsetRigidStates = nullptr;
  const PfxRigidBody* offsetRigidBodies = nullptr;
  PfxSolverBody* offsetSolverBodies = nullptr;
  PfxUInt32 numRigidBodies = 0;
  PfxFloat timeStep = 0;
  // Fraction of last step's impulses applied before iterating (0 disables warm starting).
  PfxFloat warmStartFactor = 1;
  // Rows for the position correction (pfxCorrectJointPositions) alone: each row's direction,
  // bounds, warm-started impulse, and a lock row's effective mass and push, as a full setup
  // gives them; the velocities the rows aim for (m_rhs) and the drive rows' effective masses,
  // which only a velocity solve reads, are left as they were. A friction drive still
  // measures its velocity, which its bound depends on.
  bool forPositionCorrection = false;
  // One byte per body, or none to set up every joint. Where given, only the joints with a
  // body flagged non-zero are set up again, and only those bodies take the geometric
  // stiffness into their inertia (pfxSetupSolverBodies with the same flags resets it); the
  // other joints keep the rows of the last setup, which must have been of the same kind and
  // at the same poses of their bodies, and have their push impulses cleared. Couplings are
  // all set up. The position correction's later passes set up only what the earlier moved.
  const PfxUInt8* bodiesToSetUp = nullptr;
};

// Measures each joint's coordinates and sets up its rows: locked axes hold at zero (or at
// the value of equal limits), limited axes keep within their limits and may close the gap
// to a limit within the step but not pass it, drives and friction push within their force
// limits, damping removes its fraction of the velocity. A coupling holds its follower at
// multiplier * leader + offset; one whose joints are inactive, or that is inactive itself,
// acts on no body. Rejects couplings naming joints or axes out of range
// (PFX_ERR_OUT_OF_RANGE) before changing anything.
// With a task manager the joints' rows are set up in parallel (each joint writes only its
// own); couplings follow in order.
PfxInt32 pfxSetupJointConstraints(const PfxSetupJointConstraintsParam& param,
                                  PfxTaskManager* taskManager = nullptr);

}  // namespace pfx
