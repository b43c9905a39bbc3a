// Stage (5'): after the bodies have moved, the joints' position errors are removed by
// moving the bodies, not by changing their velocities (post-stabilization). The velocity
// solve leaves every locked axis moving consistently, but a step along those velocities
// turns the bodies and opens each joint by about w^2 r dt^2 / 2; measuring the joints
// again at the new poses and projecting that error away, exactly for the trees of locked
// axes, keeps the gap of a swinging chain far below a millimetre. Given the step's
// contacts, the correction moves no two bodies deeper into each other at a contact point:
// a joint pulled back into place must not undo what the contacts' split impulses did.
#pragma once

#include "pfx/base_level/broadphase/pfx_broadphase_pair.h"
#include "pfx/base_level/collision/pfx_contact_manifold.h"
#include "pfx/base_level/joint/pfx_joint.h"
#include "pfx/base_level/joint/pfx_joint_coupling.h"
#include "pfx/base_level/rigidbody/pfx_rigid_body.h"
#include "pfx/base_level/solver/pfx_solver_body.h"
#include "pfx/base_level/task/pfx_task_manager.h"

namespace pfx {

struct PfxCorrectJointPositionsParam {
  void* workBuff = nullptr;
  PfxUInt32 workBytes = 0;
  PfxConstraintPair* jointPairs = nullptr;
  PfxUInt32 numJointPairs = 0;
  PfxJoint* offsetJoints = nullptr;
  PfxUInt32 numJoints = 0;
  PfxJointCoupling* offsetJointCouplings = nullptr;  // their errors are removed too
  PfxUInt32 numJointCouplings = 0;
  PfxRigidState* offsetRigidStates = nullptr;
  const PfxRigidBody* offsetRigidBodies = nullptr;
  PfxSolverBody* offsetSolverBodies = nullptr;  // scratch, overwritten
  PfxUInt32 numRigidBodies = 0;
  PfxFloat timeStep = 0;
  PfxUInt32 iteration = 10;  // for the rows solved iteratively (limits, loops, contacts)
  // Optional: the step's contact pairs and manifolds, as the solver set them up.
  PfxConstraintPair* contactPairs = nullptr;
  PfxUInt32 numContactPairs = 0;
  PfxContactManifold* offsetContactManifolds = nullptr;
  PfxUInt32 numContactManifolds = 0;
  // The contacts' pass (the third, see pfxCorrectJointPositions) runs when this call's
  // contact pairs hold points, and also when this is set: a world solved a group of islands
  // at a time (pfx_island_groups.h) sets it for every group when any pair of the world has
  // points, so that each group does what the world as one call would.
  bool contactPassAnyway = false;
};

// numContactPairs: the most contact pairs a call passes (none by default).
PfxUInt32 pfxGetWorkBytesOfCorrectJointPositions(PfxUInt32 numRigidBodies,
                                                 PfxUInt32 numJointPairs,
                                                 PfxUInt32 numContactPairs = 0);

// With a task manager the bodies and joints are set up, the joints' trees solved, and the
// bodies moved in parallel; the rows left to iteration are swept in joint order on one
// thread, so the result does not depend on it.
PfxInt32 pfxCorrectJointPositions(const PfxCorrectJointPositionsParam& param,
                                  PfxTaskManager* taskManager = nullptr);

}  // namespace pfx
