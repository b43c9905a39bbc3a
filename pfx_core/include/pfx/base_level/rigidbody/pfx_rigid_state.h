// Position, orientation, velocities and behaviour of one rigid body (seed chapter 2).
#pragma once

#include "pfx/base_level/base/pfx_vec_math.h"
#include "pfx/base_level/rigidbody/pfx_motion_type.h"

namespace pfx {

// The speeds a body moved by forces keeps: stage (1), pfxApplyExternalForce, cuts a faster
// one back to them, direction kept. Far beyond any body a robot meets (a rifle bullet flies
// at 1e3 m/s), they bound what a force, however large, on a body, however light, can make of
// its velocity, and so every impulse that velocity meets later. A body forces do not move
// (fixed, keyframe, trigger) keeps the velocity it is given, so it must be given one within
// them (PfxRigidState::isValid).
constexpr PfxFloat kPfxMaxLinearSpeed = PfxFloat(1e5);   // m/s
constexpr PfxFloat kPfxMaxAngularSpeed = PfxFloat(1e5);  // rad/s

class PfxRigidState {
 public:
  void reset();

  const PfxVector3& getPosition() const { return m_position; }
  const PfxQuat& getOrientation() const { return m_orientation; }
  const PfxVector3& getLinearVelocity() const { return m_linearVelocity; }
  const PfxVector3& getAngularVelocity() const { return m_angularVelocity; }
  PfxMotionType getMotionType() const { return static_cast<PfxMotionType>(m_motionType); }
  PfxUInt32 getRigidBodyId() const { return m_rigidBodyId; }
  PfxUInt32 getContactFilterSelf() const { return m_contactFilterSelf; }
  PfxUInt32 getContactFilterTarget() const { return m_contactFilterTarget; }
  bool isAsleep() const { return m_sleeping != 0; }
  bool isAwake() const { return m_sleeping == 0; }
  PfxUInt16 getSleepCount() const { return m_sleepCount; }

  // What rounding left out of the orientation and the angular velocity that pfxIntegrate
  // last wrote: it adds them back at the next step, so that a spin's round-off does not
  // pile up step after step (pfx_update_rigid_states.h). Zero for a value set from outside.
  const PfxQuat& getOrientationCarry() const { return m_orientationCarry; }
  const PfxVector3& getAngularVelocityCarry() const { return m_angularVelocityCarry; }

  void setPosition(const PfxVector3& p) { m_position = p; }
  // A value set is exact as given: the carry of the one it replaces no longer applies.
  void setOrientation(const PfxQuat& q) {
    m_orientation = q;
    m_orientationCarry.coeffs().setZero();
  }
  void setLinearVelocity(const PfxVector3& v) { m_linearVelocity = v; }
  void setAngularVelocity(const PfxVector3& w) {
    m_angularVelocity = w;
    m_angularVelocityCarry.setZero();
  }
  // A change added to the angular velocity (a torque's): the carry still applies.
  void addAngularVelocity(const PfxVector3& change) { m_angularVelocity += change; }
  // For a body whose motion is no longer the integrator's alone.
  void clearCarries() {
    m_orientationCarry.coeffs().setZero();
    m_angularVelocityCarry.setZero();
  }
  // The integrator's result with what its rounding left out.
  void setRotation(const PfxQuat& orientation, const PfxQuat& orientationCarry,
                   const PfxVector3& angularVelocity, const PfxVector3& angularVelocityCarry) {
    m_orientation = orientation;
    m_orientationCarry = orientationCarry;
    m_angularVelocity = angularVelocity;
    m_angularVelocityCarry = angularVelocityCarry;
  }
  void setMotionType(PfxMotionType t) { m_motionType = t; }
  void setRigidBodyId(PfxUInt32 id) { m_rigidBodyId = id; }
  void setContactFilterSelf(PfxUInt32 f) { m_contactFilterSelf = f; }
  void setContactFilterTarget(PfxUInt32 f) { m_contactFilterTarget = f; }
  void sleep() { m_sleeping = 1; }
  void wakeup() { m_sleeping = 0; m_sleepCount = 0; }
  void incrementSleepCount() { if (m_sleepCount < 0xffff) ++m_sleepCount; }
  void resetSleepCount() { m_sleepCount = 0; }

  PfxTransform3 getTransform() const { return pfxMakeTransform(m_orientation, m_position); }

  // A body whose position is finite, whose orientation is a unit quaternion and whose
  // velocities have finite squared lengths (the stages square them), within
  // kPfxMaxLinearSpeed and kPfxMaxAngularSpeed if forces do not move it; anything else
  // would spread NaN through the solver.
  bool isValid() const;

 private:
  // The serializer (pfx_serialize.h) restores the sleep counter as it was.
  friend class PfxSerializeAccess;

  PfxVector3 m_position;
  PfxQuat m_orientation;
  PfxVector3 m_linearVelocity;
  PfxVector3 m_angularVelocity;
  PfxUInt32 m_rigidBodyId;
  PfxUInt32 m_contactFilterSelf;
  PfxUInt32 m_contactFilterTarget;
  PfxUInt16 m_sleepCount;
  PfxUInt8 m_motionType;
  PfxUInt8 m_sleeping;
  PfxQuat m_orientationCarry;
  PfxVector3 m_angularVelocityCarry;
};

static_assert(sizeof(PfxRigidState) == 20 * sizeof(PfxFloat) + 4 * sizeof(PfxUInt32),
              "PfxRigidState must stay free of padding");

// Drives a keyframe body toward a target pose over the next step: the change of pose
// becomes the linear and angular velocity that the other bodies see (seed 4_motion_type).
// PFX_ERR_INVALID_VALUE, the state unchanged, for a non-finite target, a non-positive time
// step, or a move whose velocity isValid() would refuse (faster than kPfxMaxLinearSpeed or
// kPfxMaxAngularSpeed).
PfxInt32 pfxSetKeyframeTarget(PfxRigidState& state, const PfxVector3& targetPosition,
                              const PfxQuat& targetOrientation, PfxFloat timeStep);

// Whether two bodies' contact filters let them meet: (SelfA & TargetB) && (TargetA & SelfB).
inline bool pfxContactFiltersMatch(PfxUInt32 selfA, PfxUInt32 targetA, PfxUInt32 selfB,
                                   PfxUInt32 targetB) {
  return (selfA & targetB) != 0 && (targetA & selfB) != 0;
}

}  // namespace pfx
