// Stage (1): external forces and gravity become velocity (seed chapter 4).
#pragma once

#include "pfx/base_level/rigidbody/pfx_rigid_body.h"
#include "pfx/base_level/rigidbody/pfx_rigid_state.h"
#include "pfx/base_level/task/pfx_task_manager.h"

namespace pfx {

// One body: v += (F/m + g) dt, w += I_world^-1 T dt, each then cut to kPfxMaxLinearSpeed and
// kPfxMaxAngularSpeed. Bodies that forces do not move (fixed, keyframe, trigger) and sleeping
// bodies are left as they are.
PfxInt32 pfxApplyExternalForce(PfxRigidState& state, const PfxRigidBody& body,
                               const PfxVector3& force, const PfxVector3& torque,
                               const PfxVector3& gravity, PfxFloat timeStep);

struct PfxApplyExternalForceParam {
  PfxRigidState* states = nullptr;
  const PfxRigidBody* bodies = nullptr;
  PfxUInt32 numRigidBodies = 0;
  const PfxVector3* forces = nullptr;   // one per body, or null for none
  const PfxVector3* torques = nullptr;  // one per body, or null for none
  PfxVector3 gravity = PfxVector3(0, -9.80665f, 0);
  PfxFloat timeStep = 0;
};

// Many bodies. Every input is checked before any state is touched: a NaN force, a
// non-positive time step or a missing array is rejected and changes nothing. Bodies run in
// parallel with a task manager.
PfxInt32 pfxApplyExternalForce(const PfxApplyExternalForceParam& param,
                               PfxTaskManager* taskManager = nullptr);

}  // namespace pfx
