// A humanoid ragdoll of 16 capsule bodies held by joints whose limits keep every limb from
// bending the wrong way (seed sample 6_joint): for samples, tests and benchmarks, and as an
// example of building an articulated body from the joint functions.
#pragma once

#include "pfx/high_level/pfx_world.h"

namespace pfx {

constexpr PfxUInt32 PFX_RAGDOLL_NUM_BODIES = 16;
constexpr PfxUInt32 PFX_RAGDOLL_NUM_JOINTS = 15;

struct PfxRagdoll {
  PfxUInt32 bodies[PFX_RAGDOLL_NUM_BODIES];  // pelvis first
  PfxUInt32 joints[PFX_RAGDOLL_NUM_JOINTS];
};

// Adds a standing ragdoll about 1.8 m tall, 70 kg, arms stretched out to the sides, its
// pelvis at `pelvisPosition`, turned by `orientation`. On failure the world may hold part
// of it; the error code says what was wrong.
PfxInt32 pfxAddRagdoll(PfxWorld& world, const PfxVector3& pelvisPosition,
                       const PfxQuat& orientation, PfxRagdoll* ragdoll);

// How far a joint's coordinates, measured at the bodies' states, lie outside its locks and
// limits, in radians or metres (0 inside).
PfxFloat pfxGetJointLimitViolation(const PfxJoint& joint, const PfxRigidState& stateA,
                                   const PfxRigidState& stateB);

}  // namespace pfx
