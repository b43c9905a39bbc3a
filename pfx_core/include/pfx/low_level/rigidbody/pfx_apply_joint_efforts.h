// Stage (1'): the commanded efforts of joints (kPfxJointDriveEffort) become velocity, as
// external forces do, before the solver sees the bodies: a torque about a rotation axis or a
// force along a translation axis, cut to the axis' m_driveMaxForce, acting on body B and
// its opposite on body A. It acts along the row directions of pfxCalcJointAxes, so it does
// work on its own coordinate alone, and damping, friction, limits and the direct solve of
// joint trees then answer it as they answer gravity.
#pragma once

#include "pfx/base_level/joint/pfx_joint.h"
#include "pfx/base_level/rigidbody/pfx_rigid_body.h"
#include "pfx/base_level/rigidbody/pfx_rigid_state.h"

namespace pfx {

struct PfxApplyJointEffortsParam {
  PfxJoint* joints = nullptr;  // their axes and arms are set from the states
  PfxUInt32 numJoints = 0;
  PfxRigidState* states = nullptr;
  const PfxRigidBody* bodies = nullptr;
  PfxUInt32 numRigidBodies = 0;
  PfxFloat timeStep = 0;
};

// Every joint is checked before any state is touched: a missing array, a non-positive time
// step, an active joint with an effort naming a body out of range (PFX_ERR_OUT_OF_RANGE), or
// a NaN or infinite effort or force limit, or a negative limit (PFX_ERR_INVALID_VALUE) is
// rejected, with the detail in pfxGetLastErrorDetail(), and changes nothing. Inactive
// joints, locked axes, bodies that forces do not move and sleeping bodies are left alone.
// Joints run in order on the calling thread (two joints may share a body); allocates
// nothing.
PfxInt32 pfxApplyJointEfforts(const PfxApplyJointEffortsParam& param);

}  // namespace pfx
