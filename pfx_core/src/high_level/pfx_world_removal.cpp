// PfxWorld's removal of bodies, joints and couplings between steps (pfx_world.h explains
// the slots they leave). Each removal visits the pairs and joints once and allocates
// nothing: the free manifold list and every flag array have room already.
#include <algorithm>

#include "pfx/high_level/pfx_world.h"
#include "low_level/pfx_param_checks.h"

namespace pfx {

namespace {

// Small enough that its bounds cost nothing in a debug view, were it ever drawn.
constexpr PfxFloat kRemovedSlotRadius = PfxFloat(0.01);

}  // namespace

bool PfxWorld::couplesLiveJoints(const PfxJointCoupling& coupling) const {
  return hasJoint(coupling.m_leaderJointId) && hasJoint(coupling.m_followerJointId);
}

void PfxWorld::eraseJointedPairKey(const PfxJoint& joint) {
  const PfxUInt64 key = pfxCreatePairKey(std::min(joint.m_rigidBodyIdA, joint.m_rigidBodyIdB),
                                         std::max(joint.m_rigidBodyIdA, joint.m_rigidBodyIdB));
  m_jointedPairKeys.erase(
      std::lower_bound(m_jointedPairKeys.begin(), m_jointedPairKeys.end(), key));
}

// The pairs naming `id` leave both lists, which stay sorted, and their manifolds go back
// to the free list.
void PfxWorld::dropPairsOf(PfxUInt32 id) {
  const auto drop = [&](std::vector<PfxBroadphasePair>& pairs, PfxUInt32& numPairs) {
    const PfxUInt32 before = numPairs;
    PfxUInt32 kept = 0;
    for (PfxUInt32 i = 0; i < numPairs; ++i) {
      if (pfxGetObjectIdA(pairs[i]) != id && pfxGetObjectIdB(pairs[i]) != id) {
        pairs[kept++] = pairs[i];
      } else {
        releaseManifold(pfxGetContactId(pairs[i]));
      }
    }
    numPairs = kept;
    return kept != before;
  };
  drop(m_pairs, m_numPairs);
  // The sleeping pairs' contacts are counted over all their manifolds: only when one went.
  if (drop(m_sleepingPairs, m_numSleepingPairs)) countSleepingContacts();
}

// The slot stays an inactive coupling, so that the ids after it keep their couplings.
void PfxWorld::removeCouplingSlot(PfxUInt32 id) {
  m_jointCouplings[id].m_active = 0;
  m_removedCouplings[id] = 1;
}

// The slot stays an inactive joint between the same bodies (the low-level stages check
// every joint's ids, active or not), and those bodies may collide again.
void PfxWorld::removeJointSlot(PfxUInt32 id) {
  wakeJointBodies(id);
  for (PfxUInt32 c = 0; c < getNumJointCouplings(); ++c) {
    const PfxJointCoupling& coupling = m_jointCouplings[c];
    if (!m_removedCouplings[c] &&
        (coupling.m_leaderJointId == id || coupling.m_followerJointId == id)) {
      removeCouplingSlot(c);
    }
  }
  eraseJointedPairKey(m_joints[id]);
  m_joints[id].m_active = 0;
  m_removedJoints[id] = 1;
  ++m_numRemovedJoints;
}

PfxInt32 PfxWorld::removeJoint(PfxUInt32 id) {
  if (!hasJoint(id)) {
    return pfxRejectParam(PFX_ERR_OUT_OF_RANGE,
                          "PfxWorld::removeJoint: no joint has id %u (%u joints, %u removed)", id,
                          getNumJoints(), m_numRemovedJoints);
  }
  removeJointSlot(id);
  return PFX_OK;
}

PfxInt32 PfxWorld::removeRigidBody(PfxUInt32 id) {
  if (!hasRigidBody(id)) {
    return pfxRejectParam(PFX_ERR_OUT_OF_RANGE,
                          "PfxWorld::removeRigidBody: no body has id %u (%u bodies, %u removed)",
                          id, getNumRigidBodies(), m_numRemovedBodies);
  }
  if (particlesPinBodyIn(id, id + 1)) {
    return pfxRejectParam(PFX_ERR_INVALID_VALUE,
                          "PfxWorld::removeRigidBody: particles are pinned or tethered to body "
                          "%u; remove their group first",
                          id);
  }
  // What rested on it or hung from it wakes, before its pairs and joints are gone.
  wakeIslandOf(id);
  wakeIslandsTouching(id);
  restoreWokenPairs();
  for (PfxUInt32 j = 0; j < getNumJoints(); ++j) {
    if (!m_removedJoints[j] &&
        (m_joints[j].m_rigidBodyIdA == id || m_joints[j].m_rigidBodyIdB == id)) {
      removeJointSlot(j);
    }
  }
  // The larger id of a pair is the key's low half, the smaller the high half.
  m_excludedPairKeys.erase(std::remove_if(m_excludedPairKeys.begin(), m_excludedPairKeys.end(),
                                          [id](PfxUInt64 key) {
                                            return PfxUInt32(key) == id ||
                                                   PfxUInt32(key >> 32) == id;
                                          }),
                           m_excludedPairKeys.end());
  dropPairsOf(id);
  if (m_states[id].isAsleep()) --m_numSleepingBodies;

  PfxRigidState inert;
  inert.reset();
  inert.setPosition(m_param.worldCenter);
  inert.setMotionType(kPfxMotionTypeFixed);
  inert.setContactFilterSelf(0);
  inert.setContactFilterTarget(0);
  inert.setRigidBodyId(id);
  m_states[id] = inert;
  m_bodies[id].reset();
  PfxShape point;
  point.reset();
  point.setSphere(PfxSphere(kRemovedSlotRadius));
  m_collidables[id].reset();
  m_collidables[id].addShape(point);
  m_collidables[id].finish();
  // The shapes it held may be freed by the application once it is gone.
  m_compoundShapes[id].reset();
  m_compoundShapeIds[id].reset();
  m_forces[id].setZero();
  m_torques[id].setZero();
  m_removedBodies[id] = 1;
  ++m_numRemovedBodies;
  m_sleepingProxiesStale = true;
  m_rayProxiesStale = true;
  return PFX_OK;
}

}  // namespace pfx
