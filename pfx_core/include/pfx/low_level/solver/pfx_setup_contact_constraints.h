// Stage (4b): contact points become solver rows: one normal row that only pushes, two
// friction rows bounded by the friction cone (seed chapter 4).
#pragma once

#include "pfx/base_level/broadphase/pfx_broadphase_pair.h"
#include "pfx/base_level/collision/pfx_contact_manifold.h"
#include "pfx/base_level/rigidbody/pfx_rigid_body.h"
#include "pfx/base_level/rigidbody/pfx_rigid_state.h"
#include "pfx/base_level/solver/pfx_solver_body.h"
#include "pfx/base_level/task/pfx_task_manager.h"

namespace pfx {

struct PfxSetupContactConstraintsParam {
  PfxConstraintPair* contactPairs = nullptr;
  PfxUInt32 numContactPairs = 0;
  PfxContactManifold* offsetContactManifolds = nullptr;
  // Length of offsetContactManifolds, to check the pairs' contact ids against; 0 (the
  // seed's programs give none) checks nothing, and each pair's id must index the array.
  PfxUInt32 numContactManifolds = 0;
  const PfxRigidState* offsetRigidStates = nullptr;
  const PfxRigidBody* offsetRigidBodies = nullptr;
  PfxSolverBody* offsetSolverBodies = nullptr;
  PfxUInt32 numRigidBodies = 0;
  PfxFloat timeStep = 0;
  // Fraction of the penetration (beyond `contactSlop`) pushed out per step, by split
  // impulses that move the bodies apart without giving them velocity.
  PfxFloat separateBias = 0.2f;
  PfxFloat contactSlop = 0.005f;
  // Fraction of last frame's impulses applied before iterating (0 disables warm starting).
  PfxFloat warmStartFactor = 1.0f;
};

// Pairs run in parallel with a task manager; they must name distinct manifolds.
PfxInt32 pfxSetupContactConstraints(const PfxSetupContactConstraintsParam& param,
                                    PfxTaskManager* taskManager = nullptr);

}  // namespace pfx
