// Parameters and initialisation functions for each joint type of the seed (chapter 3,
// "Create a Joint"). Each places the joint frame at a world anchor point, with its X axis
// along the given world axis, from the two bodies' current states. With enableJointFrame
// the frame is taken from jointFrame (world, columns X, Y, Z) instead of the axis parameters.
// They return PFX_OK, or an error code and leave the joint untouched.
#pragma once

#include "pfx/base_level/broadphase/pfx_broadphase_pair.h"
#include "pfx/base_level/joint/pfx_joint.h"

namespace pfx {

struct PfxJointInitParamBase {
  PfxVector3 anchorPoint = PfxVector3::Zero();  // world
  PfxFloat damping = 0;
  PfxFloat bias = PfxFloat(1);
  bool enableJointFrame = false;
  PfxMatrix3 jointFrame = PfxMatrix3::Identity();  // world, columns are the X, Y, Z axes
};

struct PfxBallJointInitParam : PfxJointInitParamBase {};

struct PfxSwingTwistJointInitParam : PfxJointInitParamBase {
  PfxVector3 twistAxis = PfxVector3::UnitX();
  PfxFloat twistLowerAngle = -PfxFloat(0.26);
  PfxFloat twistUpperAngle = PfxFloat(0.26);
  PfxFloat swingUpperAngle = PfxFloat(0.7);  // half angle of the cone
};

struct PfxHingeJointInitParam : PfxJointInitParamBase {
  PfxVector3 axis = PfxVector3::UnitZ();
  // The full turn, which leaves the hinge unlimited. Exactly PFX_PI: a rounded literal
  // would lie inside the turn in double and stop the hinge there.
  PfxFloat lowerAngle = -PFX_PI;
  PfxFloat upperAngle = PFX_PI;
};

struct PfxSliderJointInitParam : PfxJointInitParamBase {
  PfxVector3 direction = PfxVector3::UnitX();
  PfxFloat lowerDistance = -1;
  PfxFloat upperDistance = 1;
};

struct PfxFixedJointInitParam : PfxJointInitParamBase {};

struct PfxUniversalJointInitParam : PfxJointInitParamBase {
  PfxVector3 axis = PfxVector3::UnitX();   // the locked twist axis
  PfxVector3 upVec = PfxVector3::UnitY();  // fixes the frame's Y axis about X
  PfxFloat swing1LowerAngle = -PfxFloat(0.7);
  PfxFloat swing1UpperAngle = PfxFloat(0.7);
  PfxFloat swing2LowerAngle = -PfxFloat(0.7);
  PfxFloat swing2UpperAngle = PfxFloat(0.7);
};

PfxInt32 pfxInitializeBallJoint(PfxJoint& joint, const PfxRigidState& stateA,
                                const PfxRigidState& stateB, const PfxBallJointInitParam& param);
PfxInt32 pfxInitializeSwingTwistJoint(PfxJoint& joint, const PfxRigidState& stateA,
                                      const PfxRigidState& stateB,
                                      const PfxSwingTwistJointInitParam& param);
PfxInt32 pfxInitializeHingeJoint(PfxJoint& joint, const PfxRigidState& stateA,
                                 const PfxRigidState& stateB, const PfxHingeJointInitParam& param);
PfxInt32 pfxInitializeSliderJoint(PfxJoint& joint, const PfxRigidState& stateA,
                                  const PfxRigidState& stateB,
                                  const PfxSliderJointInitParam& param);
PfxInt32 pfxInitializeFixedJoint(PfxJoint& joint, const PfxRigidState& stateA,
                                 const PfxRigidState& stateB, const PfxFixedJointInitParam& param);
PfxInt32 pfxInitializeUniversalJoint(PfxJoint& joint, const PfxRigidState& stateA,
                                     const PfxRigidState& stateB,
                                     const PfxUniversalJointInitParam& param);

// The joint's pair for the solver (seed: "Create a pair structure corresponds to the
// joints"): its bodies, motion types and whether the solver responds (not when both bodies
// sleep, or one sleeps and the other is fixed); update it whenever the joint, a body's
// motion type or its sleep changes.
void pfxUpdateJointPairs(PfxConstraintPair& pair, PfxUInt32 jointId, const PfxJoint& joint,
                         const PfxRigidState& stateA, const PfxRigidState& stateB);

}  // namespace pfx
