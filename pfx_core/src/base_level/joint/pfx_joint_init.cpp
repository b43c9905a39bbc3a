#include "pfx/base_level/joint/pfx_joint_init.h"

namespace pfx {

namespace {

// A right-handed orthonormal frame whose X axis is `axis`, with Y as close to `up` as the
// axis allows (any perpendicular when `up` is parallel to it).
bool frameFromAxis(const PfxVector3& axis, const PfxVector3& up, PfxMatrix3& frame) {
  if (!pfxIsFinite(axis) || !pfxIsFinite(up) || axis.norm() < PFX_EPSILON) return false;
  const PfxVector3 x = axis.normalized();
  PfxVector3 y = up - x * x.dot(up);
  if (y.norm() < PfxFloat(1e-3) * std::max(up.norm(), PfxFloat(1))) {
    PfxVector3 z;
    pfxGetPlaneSpace(x, y, z);
  }
  y.normalize();
  frame.col(0) = x;
  frame.col(1) = y;
  frame.col(2) = x.cross(y);
  return true;
}

bool isRotation(const PfxMatrix3& m) {
  return m.allFinite() &&
         (m.transpose() * m - PfxMatrix3::Identity()).cwiseAbs().maxCoeff() < PfxFloat(1e-3) &&
         m.determinant() > 0;
}

// Fills a joint whose frame in the world is `worldFrame` at `param.anchorPoint`, with every
// axis locked; the caller then frees or limits the axes of its type. Writes `joint` only
// when every check passes.
PfxInt32 initialize(PfxJoint& joint, const PfxRigidState& stateA, const PfxRigidState& stateB,
                    const PfxJointInitParamBase& param, PfxMatrix3 worldFrame, PfxJointType type,
                    void (*configure)(PfxJoint&, const void*), const void* typeParam) {
  if (param.enableJointFrame) worldFrame = param.jointFrame;
  if (!pfxIsFinite(param.anchorPoint) || !isRotation(worldFrame) || !stateA.isValid() ||
      !stateB.isValid() || !(param.damping >= 0 && param.damping <= 1) ||
      !(param.bias >= 0 && param.bias <= 1)) {
    return PFX_ERR_INVALID_VALUE;
  }
  if (stateA.getRigidBodyId() == stateB.getRigidBodyId()) return PFX_ERR_INVALID_VALUE;

  PfxJoint built;
  built.reset();
  built.m_type = type;
  built.m_rigidBodyIdA = stateA.getRigidBodyId();
  built.m_rigidBodyIdB = stateB.getRigidBodyId();
  const PfxMatrix3 rotationA = stateA.getOrientation().toRotationMatrix();
  const PfxMatrix3 rotationB = stateB.getOrientation().toRotationMatrix();
  built.m_anchorA = rotationA.transpose() * (param.anchorPoint - stateA.getPosition());
  built.m_anchorB = rotationB.transpose() * (param.anchorPoint - stateB.getPosition());
  built.m_frameA = rotationA.transpose() * worldFrame;
  built.m_frameB = rotationB.transpose() * worldFrame;
  for (PfxJointConstraint& c : built.m_constraints) {
    c.m_lock = kPfxJointLockLocked;
    c.m_bias = param.bias;
    c.m_damping = param.damping;
  }
  configure(built, typeParam);
  if (const PfxInt32 err = pfxCheckJoint(built); err != PFX_OK) return err;
  joint = built;
  return PFX_OK;
}

void setLimit(PfxJointConstraint& c, PfxFloat lower, PfxFloat upper) {
  c.m_lock = kPfxJointLockLimit;
  c.m_movableLowerLimit = lower;
  c.m_movableUpperLimit = upper;
}

void freeRotation(PfxJoint& joint) {
  for (PfxUInt32 i = kPfxJointAxisTwist; i <= kPfxJointAxisSwing2; ++i) {
    joint.m_constraints[i].m_lock = kPfxJointLockFree;
  }
}

}  // namespace

PfxInt32 pfxInitializeBallJoint(PfxJoint& joint, const PfxRigidState& stateA,
                                const PfxRigidState& stateB, const PfxBallJointInitParam& param) {
  return initialize(joint, stateA, stateB, param, PfxMatrix3::Identity(), kPfxJointBall,
                    [](PfxJoint& j, const void*) { freeRotation(j); }, nullptr);
}

PfxInt32 pfxInitializeSwingTwistJoint(PfxJoint& joint, const PfxRigidState& stateA,
                                      const PfxRigidState& stateB,
                                      const PfxSwingTwistJointInitParam& param) {
  PfxMatrix3 frame;
  if (!param.enableJointFrame && !frameFromAxis(param.twistAxis, PfxVector3::UnitY(), frame)) {
    return PFX_ERR_INVALID_VALUE;
  }
  if (!(param.swingUpperAngle >= 0)) return PFX_ERR_INVALID_VALUE;
  return initialize(
      joint, stateA, stateB, param, frame, kPfxJointSwingTwist,
      [](PfxJoint& j, const void* p) {
        const auto& sp = *static_cast<const PfxSwingTwistJointInitParam*>(p);
        setLimit(j.m_constraints[kPfxJointAxisTwist], sp.twistLowerAngle, sp.twistUpperAngle);
        // The cone: swing1 carries the half angle, swing2 follows it.
        setLimit(j.m_constraints[kPfxJointAxisSwing1], 0, sp.swingUpperAngle);
        j.m_constraints[kPfxJointAxisSwing2].m_lock = kPfxJointLockFree;
      },
      &param);
}

PfxInt32 pfxInitializeHingeJoint(PfxJoint& joint, const PfxRigidState& stateA,
                                 const PfxRigidState& stateB, const PfxHingeJointInitParam& param) {
  PfxMatrix3 frame;
  if (!param.enableJointFrame && !frameFromAxis(param.axis, PfxVector3::UnitY(), frame)) {
    return PFX_ERR_INVALID_VALUE;
  }
  return initialize(
      joint, stateA, stateB, param, frame, kPfxJointHinge,
      [](PfxJoint& j, const void* p) {
        const auto& hp = *static_cast<const PfxHingeJointInitParam*>(p);
        setLimit(j.m_constraints[kPfxJointAxisTwist], hp.lowerAngle, hp.upperAngle);
      },
      &param);
}

PfxInt32 pfxInitializeSliderJoint(PfxJoint& joint, const PfxRigidState& stateA,
                                  const PfxRigidState& stateB,
                                  const PfxSliderJointInitParam& param) {
  PfxMatrix3 frame;
  if (!param.enableJointFrame && !frameFromAxis(param.direction, PfxVector3::UnitY(), frame)) {
    return PFX_ERR_INVALID_VALUE;
  }
  return initialize(
      joint, stateA, stateB, param, frame, kPfxJointSlider,
      [](PfxJoint& j, const void* p) {
        const auto& sp = *static_cast<const PfxSliderJointInitParam*>(p);
        setLimit(j.m_constraints[kPfxJointAxisX], sp.lowerDistance, sp.upperDistance);
      },
      &param);
}

PfxInt32 pfxInitializeFixedJoint(PfxJoint& joint, const PfxRigidState& stateA,
                                 const PfxRigidState& stateB, const PfxFixedJointInitParam& param) {
  return initialize(joint, stateA, stateB, param, PfxMatrix3::Identity(), kPfxJointFixed,
                    [](PfxJoint&, const void*) {}, nullptr);
}

PfxInt32 pfxInitializeUniversalJoint(PfxJoint& joint, const PfxRigidState& stateA,
                                     const PfxRigidState& stateB,
                                     const PfxUniversalJointInitParam& param) {
  PfxMatrix3 frame;
  if (!param.enableJointFrame && !frameFromAxis(param.axis, param.upVec, frame)) {
    return PFX_ERR_INVALID_VALUE;
  }
  return initialize(
      joint, stateA, stateB, param, frame, kPfxJointUniversal,
      [](PfxJoint& j, const void* p) {
        const auto& up = *static_cast<const PfxUniversalJointInitParam*>(p);
        setLimit(j.m_constraints[kPfxJointAxisSwing1], up.swing1LowerAngle, up.swing1UpperAngle);
        setLimit(j.m_constraints[kPfxJointAxisSwing2], up.swing2LowerAngle, up.swing2UpperAngle);
      },
      &param);
}

void pfxUpdateJointPairs(PfxConstraintPair& pair, PfxUInt32 jointId, const PfxJoint& joint,
                         const PfxRigidState& stateA, const PfxRigidState& stateB) {
  // As pfxFindPairs does for contacts, a joint that no body of it can move (both asleep,
  // or one asleep and the other fixed) costs the solver nothing.
  const auto still = [](const PfxRigidState& s) {
    return s.isAsleep() || s.getMotionType() == kPfxMotionTypeFixed;
  };
  const bool movable = !(still(stateA) && still(stateB));
  pfxInitializeOrderedPair(pair, joint.m_rigidBodyIdA, stateA.getMotionType(),
                           joint.m_rigidBodyIdB, stateB.getMotionType(),
                           joint.m_active != 0 && movable);
  pfxSetConstraintId(pair, jointId);
}

}  // namespace pfx
