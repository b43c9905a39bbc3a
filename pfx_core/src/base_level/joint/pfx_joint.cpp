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

bool isRotation(const PfxMatrix3& m) {
  return m.allFinite() && (m.transpose() * m - PfxMatrix3::Identity()).cwiseAbs().maxCoeff() < 1e-3f &&
         m.determinant() > 0;
}

}  // namespace

PfxInt32 pfxCheckJoint(const PfxJoint& joint) {
  if (joint.m_rigidBodyIdA == joint.m_rigidBodyIdB) return PFX_ERR_INVALID_VALUE;
  if (joint.m_type >= kPfxJointTypeCount || joint.m_rotation >= kPfxJointRotationCount ||
      (joint.m_type == kPfxJointSwingTwist && joint.m_rotation != kPfxJointRotationSwingTwist)) {
    return PFX_ERR_INVALID_FLAG;
  }
  if (!pfxIsFinite(joint.m_anchorA) || !pfxIsFinite(joint.m_anchorB) ||
      !isRotation(joint.m_frameA) || !isRotation(joint.m_frameB)) {
    return PFX_ERR_INVALID_VALUE;
  }
  for (const PfxJointConstraint& c : joint.m_constraints) {
    if (c.m_lock > kPfxJointLockLimit || c.m_drive > kPfxJointDrivePosition) {
      return PFX_ERR_INVALID_FLAG;
    }
    const bool finite = pfxIsFinite(c.m_movableLowerLimit) && pfxIsFinite(c.m_movableUpperLimit) &&
                        pfxIsFinite(c.m_driveTarget) && pfxIsFinite(c.m_driveMaxForce) &&
                        pfxIsFinite(c.m_friction);
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

void pfxCalcJointCoordinates(const PfxJoint& joint, const PfxRigidState& stateA,
                             const PfxRigidState& stateB, PfxFloat coordinates[6]) {
  const PfxMatrix3 rotationA = stateA.getOrientation().toRotationMatrix();
  const PfxMatrix3 rotationB = stateB.getOrientation().toRotationMatrix();
  const PfxMatrix3 frameA = rotationA * joint.m_frameA;
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

}  // namespace pfx
