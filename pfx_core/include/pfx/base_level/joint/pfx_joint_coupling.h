// A coupling between the coordinates of two joint axes: follower = multiplier * leader +
// offset (URDF <mimic>: gripper fingers, linkages). Solved as one more constraint row with
// the joints and contacts, over the up to four bodies of the two joints.
#pragma once

#include "pfx/base_level/solver/pfx_constraint_row.h"

namespace pfx {

struct PfxJointCoupling {
  PfxUInt32 m_leaderJointId;
  PfxUInt32 m_followerJointId;
  PfxUInt8 m_leaderAxis;    // 0..5, an axis of the leader joint that is free or limited
  PfxUInt8 m_followerAxis;  // 0..5, likewise on the follower
  PfxUInt8 m_active;
  PfxUInt8 m_padding;
  PfxFloat m_multiplier;
  PfxFloat m_offset;        // m or rad
  PfxFloat m_bias;          // fraction of the error corrected per step (0..1)
  PfxFloat m_maxImpulseForce;  // largest force or torque the coupling applies; <= 0: none

  // Solver state, set up each step.
  PfxConstraintRow m_row;
};

}  // namespace pfx
