// Stage (4c): sequential impulses over contacts and joints, warm started from the last
// frame, then a restitution pass; the velocity changes are added to the states at the end
// (seed chapter 4). The locked axes of joints that form trees are solved exactly, once per
// iteration, by a direct linear-time factorization (see pfxGetWorkBytesOfSolveConstraints).
#pragma once

#include "pfx/base_level/broadphase/pfx_broadphase_pair.h"
#include "pfx/base_level/collision/pfx_contact_manifold.h"
#include "pfx/base_level/joint/pfx_joint.h"
#include "pfx/base_level/joint/pfx_joint_coupling.h"
#include "pfx/base_level/rigidbody/pfx_rigid_state.h"
#include "pfx/base_level/solver/pfx_solver_body.h"

namespace pfx {

struct PfxSolveConstraintsParam {
  void* workBuff = nullptr;
  PfxUInt32 workBytes = 0;
  PfxConstraintPair* contactPairs = nullptr;
  PfxUInt32 numContactPairs = 0;
  PfxContactManifold* offsetContactManifolds = nullptr;
  PfxUInt32 numContactManifolds = 0;
  PfxConstraintPair* jointPairs = nullptr;
  PfxUInt32 numJointPairs = 0;
  PfxJoint* offsetJoints = nullptr;  // set up by pfxSetupJointConstraints
  PfxUInt32 numJoints = 0;
  PfxJointCoupling* offsetJointCouplings = nullptr;  // set up by pfxSetupJointConstraints
  PfxUInt32 numJointCouplings = 0;
  PfxRigidState* offsetRigidStates = nullptr;
  PfxSolverBody* offsetSolverBodies = nullptr;
  PfxUInt32 numRigidBodies = 0;
  PfxUInt32 iteration = 10;
  PfxFloat timeStep = 0;  // over which the split impulses push overlapping bodies apart
  // Approach speeds below this do not bounce, so that resting contacts stay at rest.
  PfxFloat restitutionThreshold = 0.2f;
};

// Work memory for the joints' direct solve: none without joints.
PfxUInt32 pfxGetWorkBytesOfSolveConstraints(PfxUInt32 numRigidBodies, PfxUInt32 numContactPairs,
                                            PfxUInt32 numJointPairs = 0, PfxUInt32 maxTasks = 1);

PfxInt32 pfxSolveConstraints(const PfxSolveConstraintsParam& param);

}  // namespace pfx
