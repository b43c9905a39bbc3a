// Stage (5): positions and orientations advance by the solved velocities (seed chapter 4).
//
// Rotation is integrated so that a torque-free body keeps its angular momentum exactly:
// the body-frame momentum is advanced by a symmetric (Strang) splitting of the free
// rigid body into exact rotations about its principal axes. This is symplectic, so the
// energy error stays bounded instead of drifting, and the intermediate-axis instability
// (the tumbling "tennis racket" flip) is reproduced rather than damped out. The step's
// change of orientation and angular velocity is added to the state with what rounding left
// out of the last one (PfxRigidState's carries), so that round-off does not pile up over
// many small steps.
#pragma once

#include "pfx/base_level/rigidbody/pfx_rigid_body.h"
#include "pfx/base_level/rigidbody/pfx_rigid_state.h"
#include "pfx/base_level/task/pfx_task_manager.h"

namespace pfx {

// One body. Fixed and trigger bodies and sleeping bodies do not move; keyframe bodies
// move by their velocity without gyroscopic change.
void pfxIntegrate(PfxRigidState& state, const PfxRigidBody& body, PfxFloat timeStep);

struct PfxUpdateRigidStatesParam {
  PfxRigidState* states = nullptr;
  const PfxRigidBody* bodies = nullptr;
  PfxUInt32 numRigidBodies = 0;
  PfxFloat timeStep = 0;
};

// Bodies run in parallel with a task manager.
PfxInt32 pfxUpdateRigidStates(const PfxUpdateRigidStatesParam& param,
                              PfxTaskManager* taskManager = nullptr);

}  // namespace pfx
