#include "pfx/base_level/joint/pfx_joint.h"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace pfx {

void PfxJointConstraint::reset() {
  std::memset(static_cast<void*>(this), 0, sizeof(*this));
  m_lock = kPfxJointLockFree;
  m_drive = kPfxJointDriveNone;
  m_bias = 1;
  m_weight = 1;
}

void PfxJoint::reset() {
  std::memset(static_cast<void*>(this), 0, sizeof(*this));
  for (PfxJointConstraint& c : m_constraints) c.reset();
  m_frameA.setIdentity();
  m_frameB.setIdentity();
  m_anchorA.setZero();
  m_anchorB.setZero();
  m_armA.setZero();
  m_armB.setZero();
  for (PfxVector3& axis : m_axes) axis.setZero();
  m_active = 1;
  m_type = kPfxJointCustom;
}

PfxVector3 PfxJoint::getAppliedForce(PfxFloat timeStep) const {
  PfxVector3 impulse = PfxVector3::Zero();
  for (int i = 0; i < 3; ++i) {
    const PfxJointConstraint& c = m_constraints[i];
    impulse += m_axes[i] * (c.m_constraintRow.m_accumImpulse + c.m_driveRow.m_accumImpulse);
  }
  return impulse / timeStep;
}

PfxVector3 PfxJoint::getAppliedTorque(PfxFloat timeStep) const {
  PfxVector3 impulse = PfxVector3::Zero();
  for (int i = 3; i < 6; ++i) {
    const PfxJointConstraint& c = m_constraints[i];
    impulse += m_axes[i] * (c.m_constraintRow.m_accumImpulse + c.m_driveRow.m_accumImpulse);
  }
  return impulse / timeStep;
}

namespace {

bool inUnitRange(PfxFloat x) { return x >= 0 && x <= 1; }

bool isFrameRotation(const PfxMatrix3& m) {
  return m.allFinite() && (m.transpose() * m - PfxMatrix3::Identity()).cwiseAbs().maxCoeff() < 1e-3f &&
         m.determinant() > 0;
}

// Euler angles change at rates whose directions are not the frame's axes: with
// w = s1' Y + s2' Ry(s1) Z + t' Ry(s1) Rz(s2) X in A's joint frame, each rate is w dotted
// with one row of the inverse of those three columns. Near swing2 = +-pi/2 the rows grow as
// 1 / cos(swing2); a floor on that cosine keeps them finite there.
void setEulerAxes(PfxJoint& joint, const PfxMatrix3& frameA) {
  constexpr PfxFloat kMinCosine = PfxFloat(1e-2);
  const PfxFloat s1 = joint.m_constraints[kPfxJointAxisSwing1].m_position;
  const PfxFloat s2 = joint.m_constraints[kPfxJointAxisSwing2].m_position;
  const PfxFloat sin1 = std::sin(s1), cos1 = std::cos(s1), sin2 = std::sin(s2);
  const PfxFloat cos2 =
      std::copysign(std::max(std::abs(std::cos(s2)), kMinCosine), std::cos(s2));
  const PfxFloat tan2 = sin2 / cos2;
  joint.m_axes[kPfxJointAxisSwing1] = frameA * PfxVector3(-tan2 * cos1, 1, tan2 * sin1);
  joint.m_axes[kPfxJointAxisSwing2] = frameA * PfxVector3(sin1, 0, cos1);
  joint.m_axes[kPfxJointAxisTwist] = frameA * PfxVector3(cos1 / cos2, 0, -sin1 / cos2);
}

}  // namespace

PfxInt32 pfxCheckJoint(const PfxJoint& joint) {
  if (joint.m_rigidBodyIdA == joint.m_rigidBodyIdB) return PFX_ERR_INVALID_VALUE;
  if (joint.m_type >= kPfxJointTypeCount || joint.m_rotation >= kPfxJointRotationCount ||
      (joint.m_type == kPfxJointSwingTwist && joint.m_rotation != kPfxJointRotationSwingTwist)) {
    return PFX_ERR_INVALID_FLAG;
  }
  // An anchor is a lever arm that the stages square, and the position correction pulls the
  // body to it: a saved anchor 3.4e38 m from its body (finite) turned the pendulum's position
  // NaN in the first step. Held to the rule of body velocities: a finite squared length.
  if (!pfxIsFinite(joint.m_anchorA.squaredNorm()) || !pfxIsFinite(joint.m_anchorB.squaredNorm()) ||
      !isFrameRotation(joint.m_frameA) || !isFrameRotation(joint.m_frameB)) {
    return PFX_ERR_INVALID_VALUE;
  }
  for (const PfxJointConstraint& c : joint.m_constraints) {
    if (c.m_lock > kPfxJointLockLimit || c.m_drive > kPfxJointDriveEffort) {
      return PFX_ERR_INVALID_FLAG;
    }
    // The rows' impulses are what the next step warm starts with, and the limits and the
    // drive target are what the rows' errors and velocities are formed from: held to the rule
    // of body velocities (PfxRigidState::isValid), a finite square, as an impulse of 3.4e38
    // N s, and a limit or drive target of 3.4e38, made the bodies infinite in the first step.
    // The force limit stays free: its largest value means no limit.
    const auto finiteSquare = [](PfxFloat x) { return pfxIsFinite(x * x); };
    const bool finite = finiteSquare(c.m_movableLowerLimit) &&
                        finiteSquare(c.m_movableUpperLimit) && finiteSquare(c.m_driveTarget) &&
                        pfxIsFinite(c.m_driveMaxForce) && pfxIsFinite(c.m_friction) &&
                        finiteSquare(c.m_constraintRow.m_accumImpulse) &&
                        finiteSquare(c.m_driveRow.m_accumImpulse);
    if (!finite || !inUnitRange(c.m_bias) || !inUnitRange(c.m_weight) ||
        !inUnitRange(c.m_damping) || c.m_friction < 0 || c.m_driveMaxForce < 0) {
      return PFX_ERR_INVALID_VALUE;
    }
    if (c.m_lock == kPfxJointLockLimit && c.m_movableLowerLimit > c.m_movableUpperLimit) {
      return PFX_ERR_INVALID_VALUE;
    }
  }
  return PFX_OK;
}

void pfxCalcJointPositions(PfxJoint& joint, const PfxRigidState& stateA,
                           const PfxRigidState& stateB) {
  PfxFloat coordinates[6];
  pfxCalcJointCoordinates(joint, stateA, stateB, coordinates);
  for (int i = 0; i < 6; ++i) joint.m_constraints[i].m_position = coordinates[i];
}

namespace {

// pfxCalcJointCoordinates from the bodies' rotation matrices and A's joint frame in the
// world, which pfxCalcJointAxes forms anyway: a joint's setup, three times a step, then
// turns each quaternion into a matrix once.
void calcJointCoordinates(const PfxJoint& joint, const PfxRigidState& stateA,
                          const PfxRigidState& stateB, const PfxMatrix3& rotationA,
                          const PfxMatrix3& rotationB, const PfxMatrix3& frameA,
                          PfxFloat coordinates[6]) {
  const PfxVector3 offset = stateB.getPosition() + rotationB * joint.m_anchorB -
                            stateA.getPosition() - rotationA * joint.m_anchorA;
  const PfxVector3 linear = frameA.transpose() * offset;
  for (int i = 0; i < 3; ++i) coordinates[i] = linear[i];

  const PfxMatrix3 relativeMatrix = frameA.transpose() * rotationB * joint.m_frameB;
  if (joint.m_rotation == kPfxJointRotationEulerYZX) {
    // relative = Ry(s1) Rz(s2) Rx(t): its X column is (c1 c2, s2, -s1 c2), and its Y row
    // (s2, c2 ct, -c2 st).
    coordinates[kPfxJointAxisSwing1] = std::atan2(-relativeMatrix(2, 0), relativeMatrix(0, 0));
    coordinates[kPfxJointAxisSwing2] =
        std::asin(std::clamp(relativeMatrix(1, 0), PfxFloat(-1), PfxFloat(1)));
    coordinates[kPfxJointAxisTwist] = std::atan2(-relativeMatrix(1, 2), relativeMatrix(1, 1));
    return;
  }
  // Relative rotation of B's frame in A's frame, split as swing * twist about X.
  PfxQuat relative(relativeMatrix);
  if (relative.w() < 0) relative.coeffs() = -relative.coeffs();
  const PfxFloat twist = 2 * std::atan2(relative.x(), relative.w());
  const PfxQuat twistRotation(std::cos(twist / 2), std::sin(twist / 2), 0, 0);
  const PfxQuat swing = relative * twistRotation.conjugate();
  const PfxFloat swingSin = std::sqrt(swing.y() * swing.y() + swing.z() * swing.z());
  const PfxFloat swingAngle = 2 * std::atan2(swingSin, std::abs(swing.w()));
  const PfxFloat sign = swing.w() < 0 ? -1 : 1;
  const PfxFloat scale = swingSin > PfxFloat(1e-9) ? sign * swingAngle / swingSin : 2 * sign;
  coordinates[kPfxJointAxisTwist] = twist;
  coordinates[kPfxJointAxisSwing1] = swing.y() * scale;
  coordinates[kPfxJointAxisSwing2] = swing.z() * scale;
}

// With all three translations locked at zero the anchors simply coincide, and world axes
// make the rows exact: rows along A's axes would turn with A, which the Jacobian leaves
// out, and the position correction would need more passes to converge.
bool anchorsCoincide(const PfxJoint& joint) {
  for (int i = 0; i < 3; ++i) {
    const PfxJointConstraint& c = joint.m_constraints[i];
    if (c.m_lock != kPfxJointLockLocked || c.m_drive != kPfxJointDriveNone) return false;
  }
  return true;
}

PfxVector3 anchorGap(const PfxRigidState& stateA, const PfxRigidState& stateB,
                     const PfxVector3& armA, const PfxVector3& armB) {
  return stateB.getPosition() + armB - stateA.getPosition() - armA;
}

}  // namespace

void pfxCalcJointCoordinates(const PfxJoint& joint, const PfxRigidState& stateA,
                             const PfxRigidState& stateB, PfxFloat coordinates[6]) {
  const PfxMatrix3 rotationA = stateA.getOrientation().toRotationMatrix();
  const PfxMatrix3 rotationB = stateB.getOrientation().toRotationMatrix();
  calcJointCoordinates(joint, stateA, stateB, rotationA, rotationB, rotationA * joint.m_frameA,
                       coordinates);
}

void pfxCalcJointRowPositions(const PfxJoint& joint, const PfxRigidState& stateA,
                              const PfxRigidState& stateB, PfxFloat positions[6]) {
  pfxCalcJointCoordinates(joint, stateA, stateB, positions);
  if (!anchorsCoincide(joint)) return;
  const PfxVector3 gap = anchorGap(stateA, stateB, stateA.getOrientation() * joint.m_anchorA,
                                   stateB.getOrientation() * joint.m_anchorB);
  for (int i = 0; i < 3; ++i) positions[i] = gap[i];
}

void pfxCalcJointAxes(PfxJoint& joint, const PfxRigidState& stateA, const PfxRigidState& stateB) {
  const PfxMatrix3 rotationA = stateA.getOrientation().toRotationMatrix();
  const PfxMatrix3 rotationB = stateB.getOrientation().toRotationMatrix();
  const PfxMatrix3 frameA = rotationA * joint.m_frameA;
  const PfxMatrix3 frameB = rotationB * joint.m_frameB;
  joint.m_armA = stateA.getOrientation() * joint.m_anchorA;
  joint.m_armB = stateB.getOrientation() * joint.m_anchorB;

  const bool coincide = anchorsCoincide(joint);
  const PfxMatrix3 linearAxes = coincide ? PfxMatrix3::Identity() : frameA;
  for (int i = 0; i < 3; ++i) joint.m_axes[i] = linearAxes.col(i);
  const PfxVector3 twist = frameA.col(0) + frameB.col(0);
  joint.m_axes[kPfxJointAxisTwist] =
      twist.norm() > PFX_EPSILON ? PfxVector3(twist.normalized()) : PfxVector3(frameA.col(0));
  joint.m_axes[kPfxJointAxisSwing1] = frameA.col(1);
  joint.m_axes[kPfxJointAxisSwing2] = frameA.col(2);

  PfxFloat coordinates[6];
  calcJointCoordinates(joint, stateA, stateB, rotationA, rotationB, frameA, coordinates);
  for (int i = 0; i < 6; ++i) joint.m_constraints[i].m_position = coordinates[i];
  if (joint.m_rotation == kPfxJointRotationEulerYZX) setEulerAxes(joint, frameA);
  if (coincide) {
    const PfxVector3 gap = anchorGap(stateA, stateB, joint.m_armA, joint.m_armB);
    for (int i = 0; i < 3; ++i) joint.m_constraints[i].m_position = gap[i];
  }
}

}  // namespace pfx
