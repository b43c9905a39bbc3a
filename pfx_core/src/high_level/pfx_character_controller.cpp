// PfxCharacterController: the characters' parameters, bodies and commands. The sensing and
// steering of a step is in pfx_character_motion.cpp.
#include "pfx/high_level/pfx_character_controller.h"

#include <algorithm>
#include <cmath>

namespace pfx {

namespace {

bool inRange(PfxFloat value, PfxFloat lo, PfxFloat hi) {
  return pfxIsFinite(value) && value >= lo && value <= hi;
}

bool positive(PfxFloat value) { return pfxIsFinite(value) && value > 0; }

// Room for the contact points of one query: a character touches a handful of bodies, each
// giving at most a few points.
constexpr std::size_t kMaxQueryContacts = 64;

// Contacts barely turn a character, and update() sets it upright again: its inertia is this
// many times its mass (kg m^2 per kg), some 300 times a solid capsule's of its size.
constexpr PfxFloat kUprightInertiaPerMass = PfxFloat(1e2);

}  // namespace

const char* pfxGetCharacterStateName(PfxCharacterState state) {
  switch (state) {
    case kPfxCharacterStanding:
      return "standing";
    case kPfxCharacterWalking:
      return "walking";
    case kPfxCharacterJumping:
      return "jumping";
    case kPfxCharacterFalling:
      return "falling";
    case kPfxCharacterSliding:
      return "sliding";
    case kPfxCharacterLanding:
      return "landing";
    default:
      return "unknown";
  }
}

PfxInt32 pfxCheckCharacterParam(const PfxCharacterParam& param) {
  const PfxFloat maxSlopeLimit = PfxFloat(89) * PFX_PI / 180;
  const bool valid =
      positive(param.radius) && pfxIsFinite(param.height) && param.height > 2 * param.radius &&
      positive(param.mass) && inRange(param.maxStepHeight, 0, param.height - 2 * param.radius) &&
      inRange(param.maxSlope, 0, maxSlopeLimit) && positive(param.maxForce) &&
      inRange(param.airControl, 0, 1) && inRange(param.jumpSpeed, 0, PfxFloat(1e6)) &&
      positive(param.maxSpeed) && positive(param.maxFallSpeed) &&
      inRange(param.landingTime, 0, PfxFloat(1e6)) && positive(param.groundProbe);
  return valid ? PFX_OK : PFX_ERR_INVALID_VALUE;
}

PfxCharacterController::PfxCharacterController(PfxWorld& world)
    : m_world(world), m_contacts(kMaxQueryContacts) {}

PfxVector3 PfxCharacterController::up() const {
  const PfxVector3& gravity = m_world.getParam().gravity;
  return gravity.norm() > PFX_EPSILON ? PfxVector3(-gravity.normalized()) : PfxVector3::UnitY();
}

bool PfxCharacterController::isCharacter(PfxUInt32 id) const {
  return id < m_characters.size() && m_characters[id].live;
}

PfxInt32 PfxCharacterController::addCharacter(const PfxCharacterParam& param,
                                              const PfxVector3& footPosition, PfxUInt32* outId) {
  if (const PfxInt32 err = pfxCheckCharacterParam(param); err != PFX_OK) return err;
  if (!pfxIsFinite(footPosition)) return PFX_ERR_INVALID_VALUE;

  const PfxVector3 upward = up();
  PfxShape capsule;
  capsule.reset();
  capsule.setCapsule(PfxCapsule(param.height / 2 - param.radius, param.radius));
  // A capsule lies along its local X axis; the body keeps the identity orientation.
  capsule.setOffsetOrientation(PfxQuat::FromTwoVectors(PfxVector3::UnitX(), upward));

  PfxRigidBody body;
  body.reset();
  body.setMass(param.mass);
  body.setInertia(PfxMatrix3::Identity() * (param.mass * kUprightInertiaPerMass));
  body.setFriction(0);
  body.setRestitution(0);

  PfxRigidState state;
  state.reset();
  state.setPosition(footPosition + upward * (param.height / 2));
  state.setMotionType(kPfxMotionTypeActive);
  state.setContactFilterSelf(param.contactFilterSelf);
  state.setContactFilterTarget(param.contactFilterTarget);

  PfxUInt32 bodyId = 0;
  if (const PfxInt32 err = m_world.addRigidBody(state, body, &capsule, 1, &bodyId);
      err != PFX_OK) {
    return err;
  }

  if (m_characterBodies.size() <= bodyId) m_characterBodies.resize(bodyId + 1, false);
  m_characterBodies[bodyId] = true;
  const auto free = std::find_if(m_characters.begin(), m_characters.end(),
                                 [](const Character& c) { return !c.live; });
  const PfxUInt32 id = static_cast<PfxUInt32>(free - m_characters.begin());
  if (free == m_characters.end()) m_characters.emplace_back();
  Character& character = m_characters[id];
  character = Character();
  character.param = param;
  character.cosMaxSlope = std::cos(param.maxSlope);
  character.live = true;
  character.status.footPosition = footPosition;
  // Its first update finds out whether it stands or falls; standing, it does not land first.
  character.status.state = kPfxCharacterStanding;
  character.status.rigidBodyId = bodyId;
  ++m_numCharacters;
  if (m_plans.size() < m_characters.size()) m_plans.resize(m_characters.capacity());
  if (outId) *outId = id;
  return PFX_OK;
}

PfxInt32 PfxCharacterController::removeCharacter(PfxUInt32 id) {
  if (!isCharacter(id)) return PFX_ERR_OUT_OF_RANGE;
  Character& character = m_characters[id];
  if (const PfxInt32 err = m_world.removeRigidBody(character.status.rigidBodyId); err != PFX_OK) {
    return err;
  }
  m_characterBodies[character.status.rigidBodyId] = false;
  character.live = false;
  --m_numCharacters;
  return PFX_OK;
}

PfxInt32 PfxCharacterController::setDesiredVelocity(PfxUInt32 id, const PfxVector3& velocity) {
  if (!isCharacter(id)) return PFX_ERR_OUT_OF_RANGE;
  if (!pfxIsFinite(velocity)) return PFX_ERR_INVALID_VALUE;
  Character& character = m_characters[id];
  // In double, so that every finite velocity is cut to maxSpeed alike in both precisions
  // (in float the length of one near the largest float overflows).
  const Eigen::Vector3d upward = up().cast<double>();
  const Eigen::Vector3d given = velocity.cast<double>();
  Eigen::Vector3d horizontal = given - upward * upward.dot(given);
  const double speed = horizontal.norm();
  if (speed > character.param.maxSpeed) horizontal *= character.param.maxSpeed / speed;
  character.desiredVelocity = horizontal.cast<PfxFloat>();
  return PFX_OK;
}

PfxInt32 PfxCharacterController::requestJump(PfxUInt32 id) {
  if (!isCharacter(id)) return PFX_ERR_OUT_OF_RANGE;
  m_characters[id].jumpRequested = true;
  return PFX_OK;
}

PfxInt32 PfxCharacterController::getStatus(PfxUInt32 id, PfxCharacterStatus& out) const {
  if (!isCharacter(id)) return PFX_ERR_OUT_OF_RANGE;
  const Character& character = m_characters[id];
  out = character.status;
  const PfxRigidState& state = m_world.getRigidState(character.status.rigidBodyId);
  out.footPosition = state.getPosition() - up() * (character.param.height / 2);
  out.velocity = state.getLinearVelocity();
  return PFX_OK;
}

PfxInt32 PfxCharacterController::getParam(PfxUInt32 id, PfxCharacterParam& out) const {
  if (!isCharacter(id)) return PFX_ERR_OUT_OF_RANGE;
  out = m_characters[id].param;
  return PFX_OK;
}

}  // namespace pfx
