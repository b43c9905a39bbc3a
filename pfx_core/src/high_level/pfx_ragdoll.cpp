#include "pfx/high_level/pfx_ragdoll.h"

#include <cmath>

#include "pfx/base_level/joint/pfx_joint_init.h"
#include "pfx/high_level/pfx_body_init.h"

namespace pfx {

namespace {

constexpr PfxFloat kDegree = PFX_PI / 180;

struct Limb {
  PfxVector3 from;  // joint end, relative to the pelvis in the ragdoll's frame
  PfxVector3 to;    // far end
  PfxFloat radius;
  PfxFloat mass;
};

// Body segments with masses after common anthropometric tables (about 70 kg in all).
enum Part {
  kPelvis, kAbdomen, kChest, kHead,
  kUpperArmL, kForearmL, kHandL, kUpperArmR, kForearmR, kHandR,
  kThighL, kShinL, kFootL, kThighR, kShinR, kFootR
};

const Limb kLimbs[PFX_RAGDOLL_NUM_BODIES] = {
    {{0, -0.08f, 0}, {0, 0.08f, 0}, 0.13f, 11},          // pelvis
    {{0, 0.08f, 0}, {0, 0.28f, 0}, 0.12f, 9},            // abdomen
    {{0, 0.28f, 0}, {0, 0.55f, 0}, 0.14f, 16},           // chest
    {{0, 0.62f, 0}, {0, 0.80f, 0}, 0.1f, 5},             // head
    {{-0.2f, 0.5f, 0}, {-0.48f, 0.5f, 0}, 0.05f, 2},     // upper arm L
    {{-0.48f, 0.5f, 0}, {-0.74f, 0.5f, 0}, 0.04f, 1.5f}, // forearm L
    {{-0.74f, 0.5f, 0}, {-0.86f, 0.5f, 0}, 0.035f, 0.5f},
    {{0.2f, 0.5f, 0}, {0.48f, 0.5f, 0}, 0.05f, 2},
    {{0.48f, 0.5f, 0}, {0.74f, 0.5f, 0}, 0.04f, 1.5f},
    {{0.74f, 0.5f, 0}, {0.86f, 0.5f, 0}, 0.035f, 0.5f},
    {{-0.1f, -0.12f, 0}, {-0.1f, -0.52f, 0}, 0.07f, 7},  // thigh L
    {{-0.1f, -0.52f, 0}, {-0.1f, -0.92f, 0}, 0.05f, 3.5f},
    {{-0.1f, -0.92f, 0}, {-0.1f, -0.97f, 0.16f}, 0.04f, 1},
    {{0.1f, -0.12f, 0}, {0.1f, -0.52f, 0}, 0.07f, 7},
    {{0.1f, -0.52f, 0}, {0.1f, -0.92f, 0}, 0.05f, 3.5f},
    {{0.1f, -0.92f, 0}, {0.1f, -0.97f, 0.16f}, 0.04f, 1},
};

// Joints: parent, child, where (the child's joint end) and how they move.
enum Kind { kSpine, kNeck, kShoulder, kElbow, kWrist, kHip, kKnee, kAnkle };
struct Link {
  Part parent;
  Part child;
  Kind kind;
  PfxFloat side;  // -1 left, +1 right, 0 middle
};
const Link kLinks[PFX_RAGDOLL_NUM_JOINTS] = {
    {kPelvis, kAbdomen, kSpine, 0},      {kAbdomen, kChest, kSpine, 0},
    {kChest, kHead, kNeck, 0},           {kChest, kUpperArmL, kShoulder, -1},
    {kUpperArmL, kForearmL, kElbow, -1}, {kForearmL, kHandL, kWrist, -1},
    {kChest, kUpperArmR, kShoulder, 1},  {kUpperArmR, kForearmR, kElbow, 1},
    {kForearmR, kHandR, kWrist, 1},      {kPelvis, kThighL, kHip, -1},
    {kThighL, kShinL, kKnee, -1},        {kShinL, kFootL, kAnkle, -1},
    {kPelvis, kThighR, kHip, 1},         {kThighR, kShinR, kKnee, 1},
    {kShinR, kFootR, kAnkle, 1},
};

PfxInt32 makeJoint(PfxJoint& joint, const Link& link, const PfxRigidState& parent,
                   const PfxRigidState& child, const PfxVector3& anchor, const PfxQuat& turn) {
  const PfxVector3 up = turn * PfxVector3::UnitY();
  const PfxVector3 side = turn * PfxVector3::UnitX();
  const PfxVector3 forward = turn * PfxVector3::UnitZ();
  switch (link.kind) {
    case kSpine:
    case kNeck: {
      PfxSwingTwistJointInitParam p;
      p.anchorPoint = anchor;
      p.twistAxis = up;
      p.twistLowerAngle = -30 * kDegree;
      p.twistUpperAngle = 30 * kDegree;
      p.swingUpperAngle = (link.kind == kNeck ? 40 : 25) * kDegree;
      return pfxInitializeSwingTwistJoint(joint, parent, child, p);
    }
    case kShoulder: {
      PfxSwingTwistJointInitParam p;
      p.anchorPoint = anchor;
      p.twistAxis = side * link.side;
      p.twistLowerAngle = -60 * kDegree;
      p.twistUpperAngle = 60 * kDegree;
      p.swingUpperAngle = 80 * kDegree;
      return pfxInitializeSwingTwistJoint(joint, parent, child, p);
    }
    case kElbow: {
      // Bends forward only: about the vertical, toward +forward.
      PfxHingeJointInitParam p;
      p.anchorPoint = anchor;
      p.axis = up * -link.side;
      p.lowerAngle = 0;
      p.upperAngle = 145 * kDegree;
      return pfxInitializeHingeJoint(joint, parent, child, p);
    }
    case kWrist:
    case kAnkle: {
      PfxUniversalJointInitParam p;
      p.anchorPoint = anchor;
      p.axis = link.kind == kWrist ? PfxVector3(side * link.side) : up;
      p.upVec = forward;
      p.swing1LowerAngle = p.swing2LowerAngle = -40 * kDegree;
      p.swing1UpperAngle = p.swing2UpperAngle = 40 * kDegree;
      return pfxInitializeUniversalJoint(joint, parent, child, p);
    }
    case kHip: {
      PfxSwingTwistJointInitParam p;
      p.anchorPoint = anchor;
      p.twistAxis = -up;
      p.twistLowerAngle = -30 * kDegree;
      p.twistUpperAngle = 30 * kDegree;
      p.swingUpperAngle = 70 * kDegree;
      return pfxInitializeSwingTwistJoint(joint, parent, child, p);
    }
    case kKnee: {
      // Bends backward only: the shin swings toward -forward.
      PfxHingeJointInitParam p;
      p.anchorPoint = anchor;
      p.axis = -side;
      p.lowerAngle = -150 * kDegree;
      p.upperAngle = 0;
      return pfxInitializeHingeJoint(joint, parent, child, p);
    }
  }
  return PFX_ERR_INVALID_FLAG;
}

}  // namespace

PfxInt32 pfxAddRagdoll(PfxWorld& world, const PfxVector3& pelvisPosition,
                       const PfxQuat& orientation, PfxRagdoll* ragdoll) {
  if (!ragdoll) return PFX_ERR_NULL_POINTER;
  if (!pfxIsFinite(pelvisPosition) || !pfxIsUnitQuat(orientation)) return PFX_ERR_INVALID_VALUE;
  const PfxQuat turn = orientation.normalized();
  for (PfxUInt32 i = 0; i < PFX_RAGDOLL_NUM_BODIES; ++i) {
    const Limb& limb = kLimbs[i];
    const PfxVector3 axis = limb.to - limb.from;
    const PfxFloat length = axis.norm();
    PfxBodyInit init;
    init.mass = limb.mass;
    init.friction = 0.8f;
    init.position = pelvisPosition + turn * (0.5f * (limb.from + limb.to));
    // Capsules lie along X: turn X onto the limb.
    init.orientation = turn * PfxQuat::FromTwoVectors(PfxVector3::UnitX(), axis / length);
    const PfxFloat halfLength = std::max(PfxFloat(0), 0.5f * length - limb.radius * 0.5f);
    if (const PfxInt32 err = pfxAddBody(world, pfxMakeShape(PfxCapsule(halfLength, limb.radius)),
                                        init, &ragdoll->bodies[i]);
        err != PFX_OK) {
      return err;
    }
  }
  for (PfxUInt32 j = 0; j < PFX_RAGDOLL_NUM_JOINTS; ++j) {
    const Link& link = kLinks[j];
    const PfxVector3 anchor = pelvisPosition + turn * kLimbs[link.child].from;
    PfxJoint joint;
    if (const PfxInt32 err =
            makeJoint(joint, link, world.getRigidState(ragdoll->bodies[link.parent]),
                      world.getRigidState(ragdoll->bodies[link.child]), anchor, turn);
        err != PFX_OK) {
      return err;
    }
    if (const PfxInt32 err = world.addJoint(joint, &ragdoll->joints[j]); err != PFX_OK) return err;
  }
  return PFX_OK;
}

PfxFloat pfxGetJointLimitViolation(const PfxJoint& joint, const PfxRigidState& stateA,
                                   const PfxRigidState& stateB) {
  PfxFloat coordinates[6];
  pfxCalcJointCoordinates(joint, stateA, stateB, coordinates);
  PfxFloat worst = 0;
  for (PfxUInt32 axis = 0; axis < 6; ++axis) {
    const PfxJointConstraint& c = joint.m_constraints[axis];
    PfxFloat position = coordinates[axis];
    if (joint.m_type == kPfxJointSwingTwist && axis == kPfxJointAxisSwing1) {
      const PfxFloat other = coordinates[kPfxJointAxisSwing2];
      position = std::sqrt(position * position + other * other);
    } else if (joint.m_type == kPfxJointSwingTwist && axis == kPfxJointAxisSwing2) {
      continue;
    }
    if (c.m_lock == kPfxJointLockLocked) {
      worst = std::max(worst, std::abs(position));
    } else if (c.m_lock == kPfxJointLockLimit) {
      worst = std::max(worst, std::max(c.m_movableLowerLimit - position,
                                       position - c.m_movableUpperLimit));
    }
  }
  return worst;
}

}  // namespace pfx
