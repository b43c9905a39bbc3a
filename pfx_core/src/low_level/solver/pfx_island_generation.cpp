#include "pfx/low_level/solver/pfx_island_generation.h"

#include <limits>
#include <utility>

#include "low_level/pfx_buffer_checks.h"

namespace pfx {

// The header of islandBuff; the arrays follow it, placed by IslandLayout.
struct PfxIsland {
  PfxUInt32 numRigidBodies;
  PfxUInt32 numIslands;
  PfxUInt32 numContactPairs;
  PfxUInt32 numJoints;
};

namespace {

// Byte offsets of the arrays in islandBuff. The pair copies come first, where the 16-byte
// header keeps them aligned; every "start" array has one entry per island plus one, and an
// island's items are items[start[k]] up to items[start[k + 1]].
struct IslandLayout {
  PfxUInt64 pairs, islandOfBody, parent, bodyStart, bodies, pairStart, jointStart, joints, total;

  IslandLayout(PfxUInt64 numBodies, PfxUInt64 numPairs, PfxUInt64 numJoints) {
    const PfxUInt64 word = sizeof(PfxUInt32);
    pairs = sizeof(PfxIsland) < PFX_BUFFER_ALIGNMENT ? PFX_BUFFER_ALIGNMENT : sizeof(PfxIsland);
    islandOfBody = pairs + numPairs * sizeof(PfxConstraintPair);
    parent = islandOfBody + numBodies * word;
    bodyStart = parent + numBodies * word;
    bodies = bodyStart + (numBodies + 1) * word;
    pairStart = bodies + numBodies * word;
    jointStart = pairStart + (numBodies + 1) * word;
    joints = jointStart + (numBodies + 1) * word;
    total = joints + numJoints * word;
  }
};

template <typename T>
T* atOffset(void* base, PfxUInt64 offset) {
  return reinterpret_cast<T*>(static_cast<unsigned char*>(base) + offset);
}

template <typename T>
const T* atOffset(const void* base, PfxUInt64 offset) {
  return reinterpret_cast<const T*>(static_cast<const unsigned char*>(base) + offset);
}

IslandLayout layoutOf(const PfxIsland& island) {
  return IslandLayout(island.numRigidBodies, island.numContactPairs, island.numJoints);
}

bool linksBodies(const PfxRigidState& state) {
  return pfxMotionTypeIsDynamic(state.getMotionType());
}

// Union-find whose roots are always the lowest id of their set, so that the sets, and the
// numbering taken from the roots, do not depend on the order of the links.
class DisjointSets {
 public:
  DisjointSets(PfxUInt32* parent, PfxUInt32 count) : m_parent(parent) {
    for (PfxUInt32 i = 0; i < count; ++i) m_parent[i] = i;
  }

  PfxUInt32 root(PfxUInt32 x) {
    while (m_parent[x] != x) {
      m_parent[x] = m_parent[m_parent[x]];  // path halving
      x = m_parent[x];
    }
    return x;
  }

  void unite(PfxUInt32 a, PfxUInt32 b) {
    const PfxUInt32 ra = root(a), rb = root(b);
    if (ra < rb) {
      m_parent[rb] = ra;
    } else if (rb < ra) {
      m_parent[ra] = rb;
    }
  }

 private:
  PfxUInt32* m_parent;
};

// Gathers items by island with a counting sort, keeping their order: start[k] becomes the
// first slot of island k. islandOfItem(i) is an island or PFX_ISLAND_NONE (item left out).
template <typename IslandOf, typename Store>
void groupByIsland(PfxUInt32 numItems, PfxUInt32 numIslands, PfxUInt32* start,
                   IslandOf islandOfItem, Store store) {
  for (PfxUInt32 k = 0; k <= numIslands; ++k) start[k] = 0;
  for (PfxUInt32 i = 0; i < numItems; ++i) {
    const PfxUInt32 k = islandOfItem(i);
    if (k != PFX_ISLAND_NONE) ++start[k + 1];
  }
  for (PfxUInt32 k = 0; k < numIslands; ++k) start[k + 1] += start[k];
  // Each island's start serves as its cursor and ends at the next island's start...
  for (PfxUInt32 i = 0; i < numItems; ++i) {
    const PfxUInt32 k = islandOfItem(i);
    if (k != PFX_ISLAND_NONE) store(start[k]++, i);
  }
  // ...so shifting by one restores the starts.
  for (PfxUInt32 k = numIslands; k > 0; --k) start[k] = start[k - 1];
  start[0] = 0;
}

PfxInt32 checkInput(const PfxGenerateIslandParam& param, const IslandLayout& layout) {
  const PfxParamNames at{"pfxGenerateIsland", "PfxGenerateIslandParam"};
  // Checked in turn, so that the detail names the first field that is wrong.
  PfxInt32 err = PFX_OK;
  if ((err = pfxCheckRequired(at, {{param.offsetRigidStates, "offsetRigidStates"}},
                              "numRigidBodies", param.numRigidBodies)) != PFX_OK ||
      (err = pfxCheckRequired(at, {{param.contactPairs, "contactPairs"}}, "numContactPairs",
                              param.numContactPairs)) != PFX_OK ||
      (err = pfxCheckRequired(at, {{param.offsetJoints, "offsetJoints"}}, "numJoints",
                              param.numJoints)) != PFX_OK ||
      (err = pfxCheckRequired(at, {{param.offsetJointCouplings, "offsetJointCouplings"}},
                              "numJointCouplings", param.numJointCouplings)) != PFX_OK ||
      (err = pfxCheckBuffer(at, "islandBuff", param.islandBuff, param.islandBytes,
                            layout.total)) != PFX_OK) {
    return err;
  }
  const auto overlaps = [&](const void* input, PfxUInt64 bytes) {
    return pfxRangesOverlap(param.islandBuff, layout.total, input, bytes);
  };
  const std::pair<bool, const char*> inputs[] = {
      {overlaps(param.offsetRigidStates, PfxUInt64(sizeof(PfxRigidState)) * param.numRigidBodies),
       "offsetRigidStates"},
      {overlaps(param.contactPairs, PfxUInt64(sizeof(PfxConstraintPair)) * param.numContactPairs),
       "contactPairs"},
      {overlaps(param.offsetJoints, PfxUInt64(sizeof(PfxJoint)) * param.numJoints), "offsetJoints"},
      {overlaps(param.offsetJointCouplings,
                PfxUInt64(sizeof(PfxJointCoupling)) * param.numJointCouplings),
       "offsetJointCouplings"}};
  for (const auto& [overlapping, field] : inputs) {
    if (overlapping) {
      return pfxRejectParam(PFX_ERR_INVALID_VALUE,
                            "pfxGenerateIsland: PfxGenerateIslandParam::islandBuff shares bytes "
                            "with %s",
                            field);
    }
  }
  if ((err = pfxCheckPairsInRange(at, "contactPairs", param.contactPairs, param.numContactPairs,
                                  param.numRigidBodies, "", 0)) != PFX_OK) {
    return err;
  }
  const PfxUInt32 n = param.numRigidBodies;
  for (PfxUInt32 j = 0; j < param.numJoints; ++j) {
    if (param.offsetJoints[j].m_rigidBodyIdA >= n || param.offsetJoints[j].m_rigidBodyIdB >= n) {
      return pfxRejectParam(PFX_ERR_OUT_OF_RANGE,
                            "pfxGenerateIsland: PfxGenerateIslandParam::offsetJoints[%u] joins "
                            "bodies %u and %u, but numRigidBodies is %u",
                            j, param.offsetJoints[j].m_rigidBodyIdA,
                            param.offsetJoints[j].m_rigidBodyIdB, n);
    }
  }
  for (PfxUInt32 c = 0; c < param.numJointCouplings; ++c) {
    const PfxJointCoupling& coupling = param.offsetJointCouplings[c];
    if (coupling.m_leaderJointId >= param.numJoints ||
        coupling.m_followerJointId >= param.numJoints) {
      return pfxRejectParam(PFX_ERR_OUT_OF_RANGE,
                            "pfxGenerateIsland: PfxGenerateIslandParam::offsetJointCouplings[%u] "
                            "names joints %u and %u, but numJoints is %u",
                            c, coupling.m_leaderJointId, coupling.m_followerJointId,
                            param.numJoints);
    }
  }
  return PFX_OK;
}
}  // namespace

PfxUInt32 pfxGetIslandBytes(PfxUInt32 numRigidBodies, PfxUInt32 numContactPairs,
                            PfxUInt32 numJoints) {
  const PfxUInt64 bytes =
      pfxAlignBytes(IslandLayout(numRigidBodies, numContactPairs, numJoints).total);
  return bytes > std::numeric_limits<PfxUInt32>::max() ? std::numeric_limits<PfxUInt32>::max()
                                                       : static_cast<PfxUInt32>(bytes);
}

PfxInt32 pfxGenerateIsland(const PfxGenerateIslandParam& param, PfxGenerateIslandResult& result) {
  const IslandLayout layout(param.numRigidBodies, param.numContactPairs, param.numJoints);
  if (const PfxInt32 err = checkInput(param, layout); err != PFX_OK) return err;

  void* const buff = param.islandBuff;
  PfxIsland& island = *static_cast<PfxIsland*>(buff);
  const PfxUInt32 numBodies = param.numRigidBodies;
  const PfxRigidState* states = param.offsetRigidStates;
  const auto links = [&](PfxUInt32 idA, PfxUInt32 idB) {
    return linksBodies(states[idA]) && linksBodies(states[idB]);
  };

  DisjointSets sets(atOffset<PfxUInt32>(buff, layout.parent), numBodies);
  for (PfxUInt32 i = 0; i < param.numContactPairs; ++i) {
    const PfxConstraintPair& pair = param.contactPairs[i];
    const PfxUInt32 idA = pfxGetObjectIdA(pair), idB = pfxGetObjectIdB(pair);
    if (pfxGetActive(pair) && pfxGetNumConstraints(pair) > 0 && links(idA, idB)) {
      sets.unite(idA, idB);
    }
  }
  for (PfxUInt32 j = 0; j < param.numJoints; ++j) {
    const PfxJoint& joint = param.offsetJoints[j];
    if (joint.m_active && links(joint.m_rigidBodyIdA, joint.m_rigidBodyIdB)) {
      sets.unite(joint.m_rigidBodyIdA, joint.m_rigidBodyIdB);
    }
  }
  for (PfxUInt32 c = 0; c < param.numJointCouplings; ++c) {
    const PfxJointCoupling& coupling = param.offsetJointCouplings[c];
    if (!coupling.m_active) continue;
    const PfxJoint& leader = param.offsetJoints[coupling.m_leaderJointId];
    const PfxJoint& follower = param.offsetJoints[coupling.m_followerJointId];
    const PfxUInt32 ids[4] = {leader.m_rigidBodyIdA, leader.m_rigidBodyIdB,
                              follower.m_rigidBodyIdA, follower.m_rigidBodyIdB};
    PfxUInt32 first = PFX_ISLAND_NONE;
    for (const PfxUInt32 id : ids) {
      if (!linksBodies(states[id])) continue;
      if (first == PFX_ISLAND_NONE) {
        first = id;
      } else {
        sets.unite(first, id);
      }
    }
  }

  // A root is its set's lowest id, so it is numbered before any other member.
  PfxUInt32* islandOfBody = atOffset<PfxUInt32>(buff, layout.islandOfBody);
  PfxUInt32 numIslands = 0;
  for (PfxUInt32 i = 0; i < numBodies; ++i) {
    if (states[i].getMotionType() == kPfxMotionTypeFixed) {
      islandOfBody[i] = PFX_ISLAND_NONE;
      continue;
    }
    const PfxUInt32 root = sets.root(i);
    islandOfBody[i] = root == i ? numIslands++ : islandOfBody[root];
  }

  // A pair or joint belongs to the island of its body that forces move.
  const auto islandOfConstraint = [&](PfxUInt32 idA, PfxUInt32 idB) {
    if (linksBodies(states[idA])) return islandOfBody[idA];
    if (linksBodies(states[idB])) return islandOfBody[idB];
    return PFX_ISLAND_NONE;
  };
  PfxUInt32* bodies = atOffset<PfxUInt32>(buff, layout.bodies);
  groupByIsland(
      numBodies, numIslands, atOffset<PfxUInt32>(buff, layout.bodyStart),
      [&](PfxUInt32 i) { return islandOfBody[i]; },
      [&](PfxUInt32 slot, PfxUInt32 i) { bodies[slot] = i; });
  PfxConstraintPair* pairs = atOffset<PfxConstraintPair>(buff, layout.pairs);
  groupByIsland(
      param.numContactPairs, numIslands, atOffset<PfxUInt32>(buff, layout.pairStart),
      [&](PfxUInt32 i) {
        const PfxConstraintPair& pair = param.contactPairs[i];
        if (!pfxGetActive(pair) || pfxGetNumConstraints(pair) == 0) return PFX_ISLAND_NONE;
        return islandOfConstraint(pfxGetObjectIdA(pair), pfxGetObjectIdB(pair));
      },
      [&](PfxUInt32 slot, PfxUInt32 i) { pairs[slot] = param.contactPairs[i]; });
  PfxUInt32* joints = atOffset<PfxUInt32>(buff, layout.joints);
  groupByIsland(
      param.numJoints, numIslands, atOffset<PfxUInt32>(buff, layout.jointStart),
      [&](PfxUInt32 j) {
        const PfxJoint& joint = param.offsetJoints[j];
        if (!joint.m_active) return PFX_ISLAND_NONE;
        return islandOfConstraint(joint.m_rigidBodyIdA, joint.m_rigidBodyIdB);
      },
      [&](PfxUInt32 slot, PfxUInt32 j) { joints[slot] = j; });

  island.numRigidBodies = numBodies;
  island.numIslands = numIslands;
  island.numContactPairs = param.numContactPairs;
  island.numJoints = param.numJoints;
  result.island = &island;
  result.numIslands = numIslands;
  return PFX_OK;
}

PfxUInt32 pfxGetNumIslands(const PfxIsland& island) { return island.numIslands; }

PfxUInt32 pfxGetIslandId(const PfxIsland& island, PfxUInt32 rigidBodyId) {
  if (rigidBodyId >= island.numRigidBodies) return PFX_ISLAND_NONE;
  return atOffset<PfxUInt32>(&island, layoutOf(island).islandOfBody)[rigidBodyId];
}

namespace {

template <typename T>
const T* islandItems(const PfxIsland& island, PfxUInt64 startOffset, PfxUInt64 itemsOffset,
                     PfxUInt32 islandId, PfxUInt32& count) {
  count = 0;
  if (islandId >= island.numIslands) return nullptr;
  const PfxUInt32* start = atOffset<PfxUInt32>(&island, startOffset);
  count = start[islandId + 1] - start[islandId];
  return atOffset<T>(&island, itemsOffset) + start[islandId];
}

}  // namespace

const PfxUInt32* pfxGetRigidBodiesInIsland(const PfxIsland& island, PfxUInt32 islandId,
                                           PfxUInt32& count) {
  const IslandLayout layout = layoutOf(island);
  return islandItems<PfxUInt32>(island, layout.bodyStart, layout.bodies, islandId, count);
}

const PfxConstraintPair* pfxGetContactPairsInIsland(const PfxIsland& island, PfxUInt32 islandId,
                                                    PfxUInt32& count) {
  const IslandLayout layout = layoutOf(island);
  return islandItems<PfxConstraintPair>(island, layout.pairStart, layout.pairs, islandId, count);
}

const PfxUInt32* pfxGetJointsInIsland(const PfxIsland& island, PfxUInt32 islandId,
                                      PfxUInt32& count) {
  const IslandLayout layout = layoutOf(island);
  return islandItems<PfxUInt32>(island, layout.jointStart, layout.joints, islandId, count);
}

}  // namespace pfx
