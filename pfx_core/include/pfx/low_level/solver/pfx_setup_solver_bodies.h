// Stage (4a): copy what the solver needs of each body (seed chapter 4).
#pragma once

#include "pfx/base_level/rigidbody/pfx_rigid_body.h"
#include "pfx/base_level/rigidbody/pfx_rigid_state.h"
#include "pfx/base_level/solver/pfx_solver_body.h"
#include "pfx/base_level/task/pfx_task_manager.h"

namespace pfx {

struct PfxSetupSolverBodiesParam {
  const PfxRigidState* states = nullptr;
  const PfxRigidBody* bodies = nullptr;
  PfxSolverBody* solverBodies = nullptr;
  PfxUInt32 numRigidBodies = 0;
  // One byte per body, or none to set up every body. Where given, a body flagged 0 keeps
  // the mass and inertia of the last setup, which must have been at its present pose, and
  // only has the velocities that impulses gave it cleared.
  const PfxUInt8* bodiesToSetUp = nullptr;
};

// Bodies that impulses do not move (fixed, keyframe, trigger, asleep) get zero inverse
// mass and inertia. Bodies run in parallel with a task manager.
PfxInt32 pfxSetupSolverBodies(const PfxSetupSolverBodiesParam& param,
                              PfxTaskManager* taskManager = nullptr);

}  // namespace pfx
