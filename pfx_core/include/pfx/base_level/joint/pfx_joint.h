// A joint between two rigid bodies: six axes, the first three translations and the last
// three rotations of body B's joint frame relative to body A's (seed chapter 2). The
// rotation is measured as a twist about the frame's X axis and a swing of that axis about
// Y and Z, so a hinge turns about X, and a cone limit bounds the swing.
#pragma once

#include "pfx/base_level/joint/pfx_joint_constraint.h"
#include "pfx/base_level/rigidbody/pfx_rigid_state.h"

namespace pfx {

enum PfxJointType : PfxUInt8 {
  kPfxJointBall = 0,
  kPfxJointSwingTwist,
  kPfxJointHinge,
  kPfxJointSlider,
  kPfxJointFixed,
  kPfxJointUniversal,
  kPfxJointCustom,  // axes set by hand
  kPfxJointTypeCount
};

// Indices of the six axes.
enum : PfxUInt32 {
  kPfxJointAxisX = 0,
  kPfxJointAxisY,
  kPfxJointAxisZ,
  kPfxJointAxisTwist,   // rotation about X
  kPfxJointAxisSwing1,  // rotation of X about Y (a swing-twist joint: the cone's half angle)
  kPfxJointAxisSwing2,  // rotation of X about Z
};

// How the three rotation coordinates measure B's joint frame against A's.
enum PfxJointRotation : PfxUInt8 {
  // Twist about X, then the swing of X as one turn about an axis in the Y-Z plane, its
  // components on Y (swing1) and Z (swing2).
  kPfxJointRotationSwingTwist = 0,
  // Euler angles: B's frame is A's turned by swing1 about Y, then by swing2 about the
  // turned Z, then by twist about the twice-turned X. Each limit then bounds one turn of a
  // chain of three revolute joints exactly (a URDF shoulder collapsed into one joint); the
  // coordinates are singular where swing2 reaches +-pi/2.
  kPfxJointRotationEulerYZX,
  kPfxJointRotationCount
};

struct PfxJoint {
  PfxJointConstraint m_constraints[6];
  PfxMatrix3 m_frameA;   // joint frame in body A (columns: X, Y, Z axes)
  PfxMatrix3 m_frameB;   // joint frame in body B
  PfxVector3 m_anchorA;  // joint origin in body A
  PfxVector3 m_anchorB;  // joint origin in body B
  PfxUInt32 m_rigidBodyIdA;
  PfxUInt32 m_rigidBodyIdB;
  PfxUInt8 m_active;
  PfxUInt8 m_type;
  PfxUInt8 m_rotation;  // PfxJointRotation: swing-twist unless set; a cone needs swing-twist
  PfxUInt8 m_padding;

  // Set up each step: world offsets of the anchors from the bodies' centres, and the
  // world directions of the six rows.
  PfxVector3 m_armA;
  PfxVector3 m_armB;
  PfxVector3 m_axes[6];

  void reset();

  // Force (N) and torque (N m, about B's anchor) the joint applied to body B during the
  // last step, in world coordinates; body A got the opposite.
  PfxVector3 getAppliedForce(PfxFloat timeStep) const;
  PfxVector3 getAppliedTorque(PfxFloat timeStep) const;
};

// Checks what pfxInitialize...Joint and the application set: ids, limits (lower <= upper),
// bias, weight and damping in [0, 1], non-negative friction and drive force, finite values,
// rows' accumulated impulses whose squares are finite, orthonormal frames. PFX_OK or the
// error code naming what is wrong.
PfxInt32 pfxCheckJoint(const PfxJoint& joint);

// The six coordinates of the joint for the given states of its bodies: B's anchor in A's
// joint frame, then twist, swing1 and swing2 (radians) as m_rotation measures them.
void pfxCalcJointCoordinates(const PfxJoint& joint, const PfxRigidState& stateA,
                             const PfxRigidState& stateB, PfxFloat coordinates[6]);

// Recomputes the six coordinates (m_constraints[i].m_position) from the two bodies' states.
void pfxCalcJointPositions(PfxJoint& joint, const PfxRigidState& stateA,
                           const PfxRigidState& stateB);

// The six coordinates as the solver's rows measure them, which pfxCalcJointAxes leaves in
// m_position: pfxCalcJointCoordinates, but with all three translations locked and undriven
// the anchors' world gap.
void pfxCalcJointRowPositions(const PfxJoint& joint, const PfxRigidState& stateA,
                              const PfxRigidState& stateB, PfxFloat positions[6]);

// Sets m_armA, m_armB, the six row directions m_axes and the coordinates from the two
// bodies' states, as the solver's rows use them: a row's coordinate changes at the rate of
// its direction dotted with the bodies' relative motion, so an impulse along it is one
// along that coordinate alone. With all three translations locked and undriven the
// translation rows are the world's axes and their coordinates the anchors' world gap.
void pfxCalcJointAxes(PfxJoint& joint, const PfxRigidState& stateA, const PfxRigidState& stateB);

}  // namespace pfx
