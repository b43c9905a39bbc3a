// Stage (4c): sequential impulses over contacts and joints, warm started from the last
// frame, then a restitution pass; the velocity changes are added to the states at the end
// (seed chapter 4). The locked axes of joints that form trees are solved exactly, once per
// iteration, by a direct linear-time factorization (see pfxGetWorkBytesOfSolveConstraints).
//
// Order: each sweep goes over the contacts, then the joints, in pair order. With a task
// manager they are split into batches in which no moving body appears twice and each body
// meets its pairs in pair order; the pairs of a batch run in parallel, and the result is
// the same bits as the sweep in pair order, with any number of threads.
#pragma once

#include "pfx/base_level/broadphase/pfx_broadphase_pair.h"
#include "pfx/base_level/collision/pfx_contact_manifold.h"
#include "pfx/base_level/joint/pfx_joint.h"
#include "pfx/base_level/joint/pfx_joint_coupling.h"
#include "pfx/base_level/rigidbody/pfx_rigid_state.h"
#include "pfx/base_level/solver/pfx_solver_body.h"
#include "pfx/base_level/task/pfx_task_manager.h"

namespace pfx {

struct PfxSolveConstraintsParam {
  void* workBuff = nullptr;
  PfxUInt32 workBytes = 0;
  PfxConstraintPair* contactPairs = nullptr;
  PfxUInt32 numContactPairs = 0;
  PfxContactManifold* offsetContactManifolds = nullptr;
  // Length of offsetContactManifolds, to check the pairs' contact ids against; 0 (the
  // seed's programs give none) checks nothing, and each pair's id must index the array.
  PfxUInt32 numContactManifolds = 0;
  PfxConstraintPair* jointPairs = nullptr;
  PfxUInt32 numJointPairs = 0;
  PfxJoint* offsetJoints = nullptr;  // set up by pfxSetupJointConstraints
  PfxUInt32 numJoints = 0;  // to check the pairs' joint ids against; 0 checks nothing
  PfxJointCoupling* offsetJointCouplings = nullptr;  // set up by pfxSetupJointConstraints
  PfxUInt32 numJointCouplings = 0;
  PfxRigidState* offsetRigidStates = nullptr;
  PfxSolverBody* offsetSolverBodies = nullptr;
  PfxUInt32 numRigidBodies = 0;
  PfxUInt32 iteration = 10;
  // The step given to pfxSetupContactConstraints; it only scales how far a speculative
  // point that bounces is carried (the seed's solver takes none, hence a default).
  PfxFloat timeStep = PfxFloat(1) / 60;
  // Approach speeds below this do not bounce, so that resting contacts stay at rest.
  PfxFloat restitutionThreshold = 0.2f;
  // Gravity, to tell which body of a contact holds the other up for shock propagation after
  // the iterations: a pass from the ground upwards that stops each body sinking into the
  // ones under it. Zero (the default) does without it; so do steps with joints or couplings.
  PfxVector3 gravity = PfxVector3::Zero();
  // When set, receives the nodes of the largest tree of the contacts' direct solve, also
  // when the work buffer is too small for it (see pfxGetWorkBytesOfSolveConstraints).
  PfxUInt32* outContactTreeNodes = nullptr;
};

// Room for a contact tree over every body: enough for any scene.
constexpr PfxUInt32 kPfxContactTreeNodesOfAnyForest = 0xffffffffu;

// Work memory for the direct solves over the joints' and the contacts' trees and for the
// batches (a few bytes per pair and per body); the same whatever the number of tasks.
// The contacts' direct solve factors its trees a batch of whole trees at a time, in a
// scratch of contactTreeNodes nodes (over 600 bytes each) at the end of the buffer, which
// must hold the step's largest tree: the default holds one over every body. With less,
// pfxSolveConstraints returns PFX_ERR_OUT_OF_BUFFER, having changed nothing, and gives the
// nodes it needs in PfxSolveConstraintsParam::outContactTreeNodes.
PfxUInt32 pfxGetWorkBytesOfSolveConstraints(
    PfxUInt32 numRigidBodies, PfxUInt32 numContactPairs, PfxUInt32 numJointPairs = 0,
    PfxUInt32 maxTasks = 1, PfxUInt32 contactTreeNodes = kPfxContactTreeNodesOfAnyForest);

PfxInt32 pfxSolveConstraints(const PfxSolveConstraintsParam& param,
                             PfxTaskManager* taskManager = nullptr);

}  // namespace pfx
