// PfxWorld's sleep (seed 3_sleep): islands that stay still fall asleep as a whole, and wake
// as a whole when something touches them, the application changes them, or their support
// goes. The low-level stages already leave sleeping bodies alone (pfxFindPairs reports no
// pair of two sleeping bodies, or of a sleeping and a fixed one; forces, the solver and the
// integrator do not move them); this file decides who sleeps and keeps their pairs aside.
#include <algorithm>
#include <cmath>

#include "pfx/high_level/pfx_world.h"

namespace pfx {

namespace {

// Keyframe bodies sleep too, but only standing still (see PfxWorldParam::enableSleep).
bool canSleep(PfxMotionType type) {
  return pfxMotionTypeIsDynamic(type) || type == kPfxMotionTypeKeyframe;
}

bool isMovingKeyframe(const PfxRigidState& state) {
  return state.getMotionType() == kPfxMotionTypeKeyframe && state.isAwake() &&
         (!state.getLinearVelocity().isZero(0) || !state.getAngularVelocity().isZero(0));
}

// A position drive this close to its target (m or rad) has arrived.
constexpr PfxFloat kDriveArrived = PfxFloat(1e-3);

// Whether a drive of the joint still has somewhere to go, or pushes: its bodies may move
// slower than the sleep thresholds, but they are on their way and must not be stopped.
bool drives(const PfxJoint& joint) {
  for (const PfxJointConstraint& c : joint.m_constraints) {
    if ((c.m_drive == kPfxJointDriveVelocity && c.m_driveTarget != 0) ||
        (c.m_drive == kPfxJointDriveEffort && c.m_driveTarget != 0 && c.m_driveMaxForce > 0) ||
        (c.m_drive == kPfxJointDrivePosition &&
         !(std::abs(c.m_position - c.m_driveTarget) <= kDriveArrived))) {
      return true;
    }
  }
  return false;
}

bool holdsPoints(const PfxConstraintPair& pair) {
  return pfxGetActive(pair) && pfxGetNumConstraints(pair) > 0;
}

// Moves the pairs of `from` that `select` picks to `to`, both staying sorted by key: the
// picked ones go through `scratch`, then merge into `to` from its end. `to` has room for
// both lists together (PfxWorld::reservePairs).
template <typename Select>
void movePairs(PfxBroadphasePair* from, PfxUInt32& numFrom, PfxBroadphasePair* to,
               PfxUInt32& numTo, PfxBroadphasePair* scratch, Select select) {
  PfxUInt32 kept = 0, moved = 0;
  for (PfxUInt32 i = 0; i < numFrom; ++i) {
    if (select(from[i])) {
      scratch[moved++] = from[i];
    } else {
      from[kept++] = from[i];
    }
  }
  numFrom = kept;
  PfxUInt32 a = numTo, b = moved, out = numTo + moved;
  while (b > 0) {
    if (a > 0 && to[a - 1].key > scratch[b - 1].key) {
      to[--out] = to[--a];
    } else {
      to[--out] = scratch[--b];
    }
  }
  numTo += moved;
}

}  // namespace

// Whether pfxFindPairs skips the pair: no body of it can move.
bool PfxWorld::isDormant(const PfxConstraintPair& pair) const {
  const auto still = [&](PfxUInt32 id) {
    return m_states[id].isAsleep() || m_states[id].getMotionType() == kPfxMotionTypeFixed;
  };
  return still(pfxGetObjectIdA(pair)) && still(pfxGetObjectIdB(pair));
}

void PfxWorld::putToSleep(PfxUInt32 id) {
  PfxRigidState& state = m_states[id];
  state.setLinearVelocity(PfxVector3::Zero());
  state.setAngularVelocity(PfxVector3::Zero());
  state.sleep();
  ++m_numSleepingBodies;
  m_sleepingProxiesStale = true;
}

void PfxWorld::wakeBody(PfxUInt32 id) {
  PfxRigidState& state = m_states[id];
  if (state.isAwake()) return;
  state.wakeup();
  --m_numSleepingBodies;
  m_sleepingProxiesStale = true;
  m_pairsToRestore = true;
}

// The whole island of the last step that holds `id` (nothing for a fixed body).
void PfxWorld::wakeIslandOf(PfxUInt32 id) {
  if (m_numSleepingBodies == 0) return;
  const PfxUInt32 islandId = pfxGetIslandId(*m_island, id);
  if (islandId == PFX_ISLAND_NONE) {
    wakeBody(id);  // fixed, or added after the last step: awake already
    return;
  }
  PfxUInt32 count = 0;
  const PfxUInt32* bodies = pfxGetRigidBodiesInIsland(*m_island, islandId, count);
  for (PfxUInt32 i = 0; i < count; ++i) wakeBody(bodies[i]);
}

// The islands of the bodies that touch `id` (a pair with points) or are jointed to it:
// those that may rest on it.
void PfxWorld::wakeIslandsTouching(PfxUInt32 id) {
  if (m_numSleepingBodies == 0) return;
  const auto wakeOther = [&](const PfxConstraintPair& pair) {
    if (!holdsPoints(pair)) return;
    if (pfxGetObjectIdA(pair) == id) wakeIslandOf(pfxGetObjectIdB(pair));
    if (pfxGetObjectIdB(pair) == id) wakeIslandOf(pfxGetObjectIdA(pair));
  };
  for (PfxUInt32 i = 0; i < m_numPairs; ++i) wakeOther(m_pairs[i]);
  for (PfxUInt32 i = 0; i < m_numSleepingPairs; ++i) wakeOther(m_sleepingPairs[i]);
  for (const PfxJoint& joint : m_joints) {
    if (joint.m_rigidBodyIdA == id) wakeIslandOf(joint.m_rigidBodyIdB);
    if (joint.m_rigidBodyIdB == id) wakeIslandOf(joint.m_rigidBodyIdA);
  }
}

// After the application changed body `id`: its island wakes, and when it is a body that
// forces do not move (fixed, keyframe), so do the islands it may carry. A body that forces
// move carries nothing outside its own island, since touching links islands.
void PfxWorld::wakeAfterChange(PfxUInt32 id) {
  wakeIslandOf(id);
  if (!pfxMotionTypeIsDynamic(m_states[id].getMotionType())) wakeIslandsTouching(id);
  restoreWokenPairs();
}

void PfxWorld::wakeJointBodies(PfxUInt32 jointId) {
  wakeIslandOf(m_joints[jointId].m_rigidBodyIdA);
  wakeIslandOf(m_joints[jointId].m_rigidBodyIdB);
  restoreWokenPairs();
}

// The set-aside pairs that a woken body can move again go back among the awake pairs, with
// their manifolds, so that the solver sees them in this very step.
void PfxWorld::restoreWokenPairs() {
  if (!m_pairsToRestore) return;
  m_pairsToRestore = false;
  movePairs(m_sleepingPairs.data(), m_numSleepingPairs, m_pairs.data(), m_numPairs,
            m_pairScratch.data(), [&](const PfxBroadphasePair& pair) { return !isDormant(pair); });
  countSleepingContacts();
}

void PfxWorld::setAsideDormantPairs() {
  movePairs(m_pairs.data(), m_numPairs, m_sleepingPairs.data(), m_numSleepingPairs,
            m_pairScratch.data(), [&](const PfxBroadphasePair& pair) { return isDormant(pair); });
  countSleepingContacts();
}

void PfxWorld::countSleepingContacts() {
  m_sleepingContactPairs = m_sleepingContactPoints = 0;
  m_sleepingMaxPenetration = 0;
  m_numSleepingPairsAwaitingFour = 0;
  for (PfxUInt32 i = 0; i < m_numSleepingPairs; ++i) {
    const PfxBroadphasePair& pair = m_sleepingPairs[i];
    if (pfxGetContactId(pair) == m_sharedEmptyManifold) {
      m_numSleepingPairsAwaitingFour +=
          mayTouchAtSeveralPoints(pfxGetObjectIdA(pair), pfxGetObjectIdB(pair)) ? 1 : 0;
      continue;
    }
    const PfxContactManifold& manifold = m_manifolds[pfxGetContactId(pair)];
    if (manifold.getNumContacts() == 0) continue;
    ++m_sleepingContactPairs;
    m_sleepingContactPoints += manifold.getNumContacts();
    m_sleepingMaxPenetration = std::max(m_sleepingMaxPenetration, manifold.getPenetrationDepth());
  }
}

// Between collision detection and the solver: an island that holds awake and sleeping
// bodies (an awake body came to touch a sleeping one, and touching made them one island)
// wakes whole, as does an island that a moving keyframe body touches or drags by a joint.
void PfxWorld::wakeTouchedIslands() {
  if (!m_param.enableSleep || m_numSleepingBodies == 0) return;
  constexpr PfxUInt8 kHasAwake = 1, kHasAsleep = 2;
  const PfxUInt32 numIslands = pfxGetNumIslands(*m_island);
  std::fill(m_islandMarks.begin(), m_islandMarks.begin() + numIslands, PfxUInt8(0));
  for (PfxUInt32 id = 0; id < getNumRigidBodies(); ++id) {
    const PfxUInt32 islandId = pfxGetIslandId(*m_island, id);
    if (islandId != PFX_ISLAND_NONE) {
      m_islandMarks[islandId] |= m_states[id].isAsleep() ? kHasAsleep : kHasAwake;
    }
  }
  for (PfxUInt32 islandId = 0; islandId < numIslands; ++islandId) {
    if (m_islandMarks[islandId] != (kHasAwake | kHasAsleep)) continue;
    PfxUInt32 count = 0;
    const PfxUInt32* bodies = pfxGetRigidBodiesInIsland(*m_island, islandId, count);
    for (PfxUInt32 i = 0; i < count; ++i) wakeBody(bodies[i]);
  }
  const auto wakeIfDragged = [&](PfxUInt32 keyframe, PfxUInt32 other) {
    if (isMovingKeyframe(m_states[keyframe]) && m_states[other].isAsleep()) wakeIslandOf(other);
  };
  for (PfxUInt32 i = 0; i < m_numPairs; ++i) {
    if (!holdsPoints(m_pairs[i])) continue;
    wakeIfDragged(pfxGetObjectIdA(m_pairs[i]), pfxGetObjectIdB(m_pairs[i]));
    wakeIfDragged(pfxGetObjectIdB(m_pairs[i]), pfxGetObjectIdA(m_pairs[i]));
  }
  for (const PfxJoint& joint : m_joints) {
    if (!joint.m_active) continue;
    wakeIfDragged(joint.m_rigidBodyIdA, joint.m_rigidBodyIdB);
    wakeIfDragged(joint.m_rigidBodyIdB, joint.m_rigidBodyIdA);
  }
  restoreWokenPairs();
}

// After the step: count how long each body has been still (a body a drive moves is never
// still), put to sleep the islands whose bodies have all been still long enough, and set
// their pairs aside.
void PfxWorld::updateSleep() {
  if (!m_param.enableSleep) return;
  const PfxUInt32 stepsToSleep = std::max<PfxUInt32>(
      1, static_cast<PfxUInt32>(std::ceil(double(m_param.sleepTime) / m_param.timeStep)));
  const PfxFloat linearSq = m_param.sleepLinearVelocity * m_param.sleepLinearVelocity;
  const PfxFloat angularSq = m_param.sleepAngularVelocity * m_param.sleepAngularVelocity;
  for (PfxRigidState& state : m_states) {
    if (state.isAsleep() || !canSleep(state.getMotionType())) continue;
    const bool still = state.getMotionType() == kPfxMotionTypeKeyframe
                           ? !isMovingKeyframe(state)
                           : state.getLinearVelocity().squaredNorm() < linearSq &&
                                 state.getAngularVelocity().squaredNorm() < angularSq;
    if (still) {
      state.incrementSleepCount();
    } else {
      state.resetSleepCount();
    }
  }
  for (const PfxJoint& joint : m_joints) {
    if (!joint.m_active || !drives(joint)) continue;
    m_states[joint.m_rigidBodyIdA].resetSleepCount();
    m_states[joint.m_rigidBodyIdB].resetSleepCount();
  }
  bool fellAsleep = false;
  for (PfxUInt32 islandId = 0; islandId < pfxGetNumIslands(*m_island); ++islandId) {
    PfxUInt32 count = 0;
    const PfxUInt32* bodies = pfxGetRigidBodiesInIsland(*m_island, islandId, count);
    bool ready = true;
    for (PfxUInt32 i = 0; i < count && ready; ++i) {
      const PfxRigidState& state = m_states[bodies[i]];
      ready = state.isAwake() && canSleep(state.getMotionType()) &&
              state.getSleepCount() >= stepsToSleep;
    }
    if (!ready) continue;
    for (PfxUInt32 i = 0; i < count; ++i) putToSleep(bodies[i]);
    fellAsleep = true;
  }
  if (fellAsleep) setAsideDormantPairs();
}

// Before truncate removes bodies, joints and couplings: the kept bodies that touched or were
// jointed to removed ones, or were coupled through removed couplings, wake with their islands.
void PfxWorld::wakeBeforeTruncate(PfxUInt32 numBodies, PfxUInt32 numJoints,
                                  PfxUInt32 numJointCouplings) {
  if (m_numSleepingBodies == 0) return;
  const auto wakeKept = [&](PfxUInt32 idA, PfxUInt32 idB) {
    if (idA < numBodies && idB >= numBodies) wakeIslandOf(idA);
    if (idB < numBodies && idA >= numBodies) wakeIslandOf(idB);
  };
  const auto wakeKeptOf = [&](const PfxConstraintPair& pair) {
    if (holdsPoints(pair)) wakeKept(pfxGetObjectIdA(pair), pfxGetObjectIdB(pair));
  };
  for (PfxUInt32 i = 0; i < m_numPairs; ++i) wakeKeptOf(m_pairs[i]);
  for (PfxUInt32 i = 0; i < m_numSleepingPairs; ++i) wakeKeptOf(m_sleepingPairs[i]);
  const auto wakeJoint = [&](PfxUInt32 jointId) {
    const PfxJoint& joint = m_joints[jointId];
    if (joint.m_rigidBodyIdA < numBodies) wakeIslandOf(joint.m_rigidBodyIdA);
    if (joint.m_rigidBodyIdB < numBodies) wakeIslandOf(joint.m_rigidBodyIdB);
  };
  for (PfxUInt32 j = numJoints; j < getNumJoints(); ++j) wakeJoint(j);
  for (PfxUInt32 c = numJointCouplings; c < getNumJointCouplings(); ++c) {
    wakeJoint(m_jointCouplings[c].m_leaderJointId);
    wakeJoint(m_jointCouplings[c].m_followerJointId);
  }
  restoreWokenPairs();
}

void PfxWorld::gatherSleepStats() {
  const PfxUInt32 numIslands = pfxGetNumIslands(*m_island);
  m_stats.numIslands = numIslands;
  m_stats.numSleepingIslands = 0;
  for (PfxUInt32 islandId = 0; islandId < numIslands; ++islandId) {
    PfxUInt32 count = 0;
    const PfxUInt32* bodies = pfxGetRigidBodiesInIsland(*m_island, islandId, count);
    if (count > 0 && m_states[bodies[0]].isAsleep()) ++m_stats.numSleepingIslands;
  }
  PfxUInt32 numMoving = 0;
  for (const PfxRigidState& state : m_states) {
    numMoving += state.getMotionType() != kPfxMotionTypeFixed;
  }
  m_stats.numSleepingBodies = m_numSleepingBodies;
  m_stats.numAwakeBodies = numMoving - m_numSleepingBodies;
  m_stats.numSleepingPairs = m_numSleepingPairs;
  m_stats.numContactPairs += m_sleepingContactPairs;
  m_stats.numContactPoints += m_sleepingContactPoints;
  m_stats.maxPenetration = std::max(m_stats.maxPenetration, m_sleepingMaxPenetration);
}

}  // namespace pfx
