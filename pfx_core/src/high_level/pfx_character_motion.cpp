// PfxCharacterController::update: sensing the ground and walls through the world's contact
// query, the state machine, steps up and down, and the velocity each body is given.
#include <algorithm>
#include <cmath>
#include <limits>

#include "pfx/high_level/pfx_character_controller.h"

namespace pfx {

namespace {

// Gap left below a body put onto a surface (m), so that it does not start the step inside.
constexpr PfxFloat kSkin = PfxFloat(0.002);
// Overlap that still counts as room for the capsule (m): resting contacts sink by about the
// world's contact slop, and a step up must not fail on that.
constexpr PfxFloat kRoomTolerance = PfxFloat(0.02);
// A walkable top less than this above the foot is no step (m): it is the ground the foot
// stands on, sunk into by up to the world's contact slop, and the capsule's round bottom
// rides over so small an edge anyway. Taking it for a step moved a character a radius
// forward, into whatever blocked it: a steep ramp's foot in the characters benchmark, where
// the capsule ended 0.19 m inside the ramp.
constexpr PfxFloat kLowestStep = PfxFloat(0.02);
// Desired speeds below this are standing still (m/s).
constexpr PfxFloat kStandingSpeed = PfxFloat(0.05);
// A steep surface whose normal points up by less than this (cosine) is a wall, not a slope
// to slide on; one pointing down by more is a ceiling and does not block walking.
constexpr PfxFloat kWallCosine = PfxFloat(0.05);
constexpr PfxFloat kCeilingCosine = PfxFloat(-0.1);
// Velocity changes below this are not written back (m/s), so that a character at rest is
// left alone and may fall asleep with its island.
constexpr PfxFloat kUnchangedVelocity = PfxFloat(1e-4);

PfxVector3 clampLength(const PfxVector3& v, PfxFloat maxLength) {
  const PfxFloat length = v.norm();
  return length > maxLength ? PfxVector3(v * (maxLength / length)) : v;
}

}  // namespace

PfxInt32 PfxCharacterController::update() {
  const PfxUInt32 count = getIdLimit();
  for (PfxUInt32 id = 0; id < count; ++id) {
    m_plans[id].write = false;
    if (!m_characters[id].live) continue;
    if (const PfxInt32 err = sense(m_characters[id], m_plans[id]); err != PFX_OK) return err;
  }
  for (PfxUInt32 id = 0; id < count; ++id) {
    const Plan& plan = m_plans[id];
    if (!plan.write) continue;
    const PfxUInt32 bodyId = m_characters[id].status.rigidBodyId;
    PfxRigidState state = m_world.getRigidState(bodyId);
    state.setPosition(plan.position);
    state.setLinearVelocity(plan.velocity);
    state.setOrientation(PfxQuat::Identity());
    state.setAngularVelocity(PfxVector3::Zero());
    if (const PfxInt32 err = m_world.setRigidState(bodyId, state); err != PFX_OK) return err;
  }
  return PFX_OK;
}

// The contacts of the character's capsule placed at `center`, within `threshold`, into
// m_contacts.
PfxInt32 PfxCharacterController::query(const Character& character, const PfxVector3& center,
                                       PfxFloat threshold, PfxUInt32& numContacts) {
  PfxContactQueryInput in;
  in.collidable = &m_world.getCollidable(character.status.rigidBodyId);
  in.transform = pfxMakeTransform(PfxQuat::Identity(), center);
  in.contactThreshold = threshold;
  in.contactFilterSelf = character.param.contactFilterSelf;
  in.contactFilterTarget = character.param.contactFilterTarget;
  in.ignoreRigidBodyId = character.status.rigidBodyId;
  PfxQueryContactsResult result;
  const PfxInt32 err = m_world.queryContacts(in, m_contacts.data(),
                                             static_cast<PfxUInt32>(m_contacts.size()), result);
  numContacts = 0;
  if (err != PFX_OK) return err;
  // Only what would push the body back counts: a trigger is passed through, never stood on.
  for (PfxUInt32 i = 0; i < result.numContacts; ++i) {
    const PfxMotionType type = m_world.getRigidState(m_contacts[i].m_rigidBodyId).getMotionType();
    if (pfxMotionTypesRespond(kPfxMotionTypeActive, type))
      m_contacts[numContacts++] = m_contacts[i];
  }
  return PFX_OK;
}

// The walkable surface least far below the capsule; of two equally far, the flatter. Other
// characters are no ground: a head is round and moves of its own will, so a character that
// lands on one slides off.
PfxCharacterController::Ground PfxCharacterController::findGround(const Character& character,
                                                                  PfxUInt32 numContacts) const {
  const PfxVector3 upward = up();
  Ground ground;
  for (PfxUInt32 i = 0; i < numContacts; ++i) {
    const PfxContactCandidate& contact = m_contacts[i].m_contact;
    const PfxVector3 normal = -contact.m_normal;  // out of the surface, towards the capsule
    const PfxFloat cosine = normal.dot(upward);
    if (cosine < character.cosMaxSlope || cosine <= 0 ||
        isCharacterBody(m_contacts[i].m_rigidBodyId)) {
      continue;
    }
    // How far the capsule would move straight down to touch the surface's plane.
    const PfxFloat drop = contact.m_distance / cosine;
    const bool closer = drop < ground.drop - kSkin;
    const bool asClose = drop < ground.drop + kSkin;
    if (!ground.found || closer || (asClose && cosine > ground.normal.dot(upward))) {
      ground.found = true;
      ground.drop = drop;
      ground.bodyId = m_contacts[i].m_rigidBodyId;
      ground.normal = normal;
    }
  }
  return ground;
}

// The velocity at which a point at `center` riding the ground moves over the next step:
// the ground's move and turn as the world integrates them (the exact rotation of its
// angular velocity), so that a platform carries a character round without drift. Only
// keyframe ground carries: a loose body under the feet is moved by the feet themselves, and
// taking on its motion would feed that back.
PfxVector3 PfxCharacterController::groundVelocity(const Ground& ground,
                                                  const PfxVector3& center) const {
  if (!ground.found) return PfxVector3::Zero();
  const PfxRigidState& state = m_world.getRigidState(ground.bodyId);
  if (state.getMotionType() != kPfxMotionTypeKeyframe) return PfxVector3::Zero();
  const PfxFloat timeStep = m_world.getParam().timeStep;
  const PfxVector3 arm = center - state.getPosition();
  const PfxVector3 turn = state.getAngularVelocity() * timeStep;
  const PfxFloat angle = turn.norm();
  const PfxVector3 turnedArm =
      angle > PFX_EPSILON ? PfxVector3(Eigen::AngleAxis<PfxFloat>(angle, turn / angle) * arm) : arm;
  return state.getLinearVelocity() + (turnedArm - arm) / timeStep;
}

// `velocity` without its parts into the touched walls and steep slopes of bodies that forces
// do not move. Loose bodies are not walls: the solver lets the character push them.
PfxVector3 PfxCharacterController::withoutWalls(const Character& character, PfxUInt32 numContacts,
                                                PfxVector3 velocity, bool& againstSteep,
                                                bool& blockedLow) const {
  const PfxVector3 upward = up();
  const PfxVector3 center = m_world.getRigidState(character.status.rigidBodyId).getPosition();
  const PfxVector3 foot = center - upward * (character.param.height / 2);
  againstSteep = blockedLow = false;
  // Twice, so that in a corner the part removed for one wall does not push into the other.
  for (int pass = 0; pass < 2; ++pass) {
    for (PfxUInt32 i = 0; i < numContacts; ++i) {
      const PfxContactCandidate& contact = m_contacts[i].m_contact;
      if (contact.m_distance > character.param.groundProbe) continue;
      const PfxVector3 normal = -contact.m_normal;
      const PfxFloat cosine = normal.dot(upward);
      if (cosine >= character.cosMaxSlope || cosine < kCeilingCosine) continue;
      if (pfxMotionTypeIsDynamic(
              m_world.getRigidState(m_contacts[i].m_rigidBodyId).getMotionType())) {
        continue;
      }
      PfxVector3 across = normal - upward * cosine;
      if (across.norm() < PFX_EPSILON) continue;
      across.normalize();
      if (cosine > kWallCosine) againstSteep = true;
      const PfxFloat into = velocity.dot(across);
      if (into >= 0) continue;
      if (pass == 0 && (contact.m_pointA - foot).dot(upward) <= character.param.maxStepHeight) {
        blockedLow = true;
      }
      velocity -= across * into;
    }
  }
  return velocity;
}

// How far the capsule can move straight down before it meets any surface below it, as far as
// the sensed contacts tell: the ground is one of them, but so is the rim of a step beside
// the feet, too steep to stand on, which a snap down to the ground below would drive the
// capsule's side into. Each surface counts as the plane through its contact point, which
// is never further than the surface itself.
PfxFloat PfxCharacterController::clearanceBelow(PfxUInt32 numContacts) const {
  const PfxVector3 upward = up();
  PfxFloat clearance = std::numeric_limits<PfxFloat>::max();
  for (PfxUInt32 i = 0; i < numContacts; ++i) {
    const PfxContactCandidate& contact = m_contacts[i].m_contact;
    const PfxFloat cosine = -contact.m_normal.dot(upward);
    if (cosine <= kWallCosine) continue;
    clearance = std::min(clearance, contact.m_distance / cosine);
  }
  return clearance;
}

// Whether a step lies ahead in `direction`: room for the capsule lifted by maxStepHeight,
// then moved forward by its radius (its axis then stands over the step's edge, whose top is
// ground under it), and a walkable top there no higher than maxStepHeight above the foot.
// `rise` is that height, or 0 when there is no step.
PfxInt32 PfxCharacterController::tryStepUp(const Character& character, const PfxVector3& center,
                                           const PfxVector3& direction, PfxFloat& rise) {
  rise = 0;
  const PfxVector3 upward = up();
  const PfxCharacterParam& param = character.param;
  const PfxFloat lift = param.maxStepHeight + kSkin;
  const auto hasRoom = [&](PfxUInt32 numContacts) {
    for (PfxUInt32 i = 0; i < numContacts; ++i) {
      if (m_contacts[i].m_contact.m_distance < -kRoomTolerance) return false;
    }
    return true;
  };
  PfxUInt32 numContacts = 0;
  const PfxVector3 lifted = center + upward * lift;
  if (const PfxInt32 err = query(character, lifted, 0, numContacts); err != PFX_OK) return err;
  if (!hasRoom(numContacts)) return PFX_OK;
  const PfxVector3 ahead = lifted + direction * param.radius;
  const PfxFloat reach = lift + param.groundProbe;
  if (const PfxInt32 err = query(character, ahead, reach, numContacts); err != PFX_OK) return err;
  if (!hasRoom(numContacts)) return PFX_OK;
  const PfxVector3 foot = center - upward * (param.height / 2);
  PfxFloat top = 0;
  for (PfxUInt32 i = 0; i < numContacts; ++i) {
    const PfxContactCandidate& contact = m_contacts[i].m_contact;
    if (-contact.m_normal.dot(upward) < character.cosMaxSlope) continue;
    top = std::max(top, (contact.m_pointB - foot).dot(upward));
  }
  if (top > kLowestStep && top <= param.maxStepHeight) rise = top;
  return PFX_OK;
}

void PfxCharacterController::transition(Character& character, PfxCharacterState state) const {
  if (character.status.state == state) {
    character.status.timeInState += m_world.getParam().timeStep;
  } else {
    character.status.state = state;
    character.status.timeInState = 0;
  }
}

// The state machine: what the character does this step decides its state.
void PfxCharacterController::advanceState(Character& character, bool jumped, bool onGround,
                                          bool rising, bool againstSteep) const {
  const PfxCharacterState previous = character.status.state;
  const bool wasInAir = previous == kPfxCharacterJumping || previous == kPfxCharacterFalling ||
                        previous == kPfxCharacterSliding;
  if (jumped) {
    transition(character, kPfxCharacterJumping);
  } else if (onGround) {
    const bool stillLanding =
        previous == kPfxCharacterLanding &&
        character.status.timeInState + m_world.getParam().timeStep < character.param.landingTime;
    if (wasInAir || stillLanding) {
      transition(character, kPfxCharacterLanding);
    } else {
      transition(character, character.desiredVelocity.norm() > kStandingSpeed
                                ? kPfxCharacterWalking
                                : kPfxCharacterStanding);
    }
  } else if (rising) {
    transition(character, kPfxCharacterJumping);
  } else {
    transition(character, againstSteep ? kPfxCharacterSliding : kPfxCharacterFalling);
  }
}

PfxInt32 PfxCharacterController::sense(Character& character, Plan& plan) {
  const PfxCharacterParam& param = character.param;
  PfxCharacterStatus& status = character.status;
  const PfxRigidState& body = m_world.getRigidState(status.rigidBodyId);
  const PfxWorldParam& worldParam = m_world.getParam();
  const PfxFloat timeStep = worldParam.timeStep;
  const PfxVector3 upward = up();
  const PfxVector3 center = body.getPosition();
  const PfxVector3 velocity = body.getLinearVelocity();

  const bool rising = status.state == kPfxCharacterJumping && velocity.dot(upward) > 0;
  const bool wasOnGround = status.groundBodyId != PFX_CHARACTER_NO_GROUND;
  // After a step on the ground, ground is sought a step's height further down.
  const PfxFloat reach = param.groundProbe + (wasOnGround ? param.maxStepHeight : 0);
  PfxUInt32 numContacts = 0;
  if (const PfxInt32 err = query(character, center, reach, numContacts); err != PFX_OK) {
    return err;
  }
  const Ground ground = findGround(character, numContacts);
  // Read now: a step up's queries below overwrite m_contacts.
  const PfxFloat clearance = clearanceBelow(numContacts);
  const bool onGround =
      !rising && ground.found && (ground.drop <= param.groundProbe || wasOnGround);

  bool againstSteep = false, blockedLow = false;
  PfxVector3 desired =
      withoutWalls(character, numContacts, character.desiredVelocity, againstSteep, blockedLow);
  PfxVector3 position = center;
  if (onGround && blockedLow && character.desiredVelocity.norm() > kStandingSpeed) {
    PfxFloat rise = 0;
    if (const PfxInt32 err =
            tryStepUp(character, center, character.desiredVelocity.normalized(), rise);
        err != PFX_OK) {
      return err;
    }
    if (rise > 0) {
      position += upward * (rise + kSkin) + character.desiredVelocity.normalized() * param.radius;
      desired = character.desiredVelocity;
      ++status.numSteps;
    }
  }
  // The snap down stops at anything in the way, such as the rim of a step beside the feet;
  // held up there, the character falls off the rim (below) instead of being driven into it.
  bool heldAboveGround = false;
  if (onGround && position == center && ground.drop > 2 * kSkin) {
    const PfxFloat drop = std::min(ground.drop, clearance);
    heldAboveGround = drop < ground.drop - kSkin;
    if (drop > 2 * kSkin) position -= upward * (drop - kSkin);
  }

  const PfxFloat maxChange = param.maxForce / param.mass * timeStep;
  PfxVector3 next = velocity;
  bool jumped = false;
  if (onGround) {
    const PfxVector3& normal = ground.normal;
    const PfxVector3 carried = groundVelocity(ground, center);
    const PfxVector3 relative = velocity - carried;
    const PfxVector3 along = relative - normal * normal.dot(relative);
    // The desired velocity laid onto the ground's plane, at its own speed.
    PfxVector3 target = desired - upward * (desired.dot(normal) / normal.dot(upward));
    if (target.norm() > PFX_EPSILON) target *= desired.norm() / target.norm();
    const PfxVector3 steered = along + clampLength(target - along, maxChange);
    jumped = character.jumpRequested;
    if (jumped) {
      next = carried + steered + upward * param.jumpSpeed;
    } else {
      // Feet hold against gravity's pull along the slope; its part into the ground the
      // contact takes.
      const PfxVector3& gravity = worldParam.gravity;
      next = carried + steered - (gravity - normal * normal.dot(gravity)) * timeStep;
      if (heldAboveGround) {
        // Gravity as in the air, the fall so far kept: the solver slides the capsule along
        // the rim that holds it, down onto the ground.
        next += upward * std::min(velocity.dot(upward), PfxFloat(0)) + gravity * timeStep;
      }
    }
  } else if (desired.norm() > PFX_EPSILON) {
    // In the air it only speeds up towards the desired velocity: braking there would hold
    // it on a slope too steep to stand on.
    const PfxVector3 direction = desired.normalized();
    const PfxFloat missing = desired.norm() - velocity.dot(direction);
    if (missing > 0) next += direction * std::min(missing, param.airControl * maxChange);
  }
  const PfxFloat fall = -next.dot(upward);
  if (fall > param.maxFallSpeed) next += upward * (fall - param.maxFallSpeed);
  character.jumpRequested = false;

  advanceState(character, jumped, onGround, rising, againstSteep);
  const bool onGroundAfter = onGround && !jumped;
  status.groundBodyId = onGroundAfter ? ground.bodyId : PFX_CHARACTER_NO_GROUND;
  status.groundNormal = onGroundAfter ? ground.normal : PfxVector3::Zero();

  const bool upright = body.getOrientation().coeffs().isApprox(PfxQuat::Identity().coeffs()) &&
                       body.getAngularVelocity().isZero(kUnchangedVelocity);
  plan.position = position;
  plan.velocity = next;
  plan.write = position != center || !upright || (next - velocity).norm() > kUnchangedVelocity;
  return PFX_OK;
}

}  // namespace pfx
