#include "high_level/pfx_island_groups.h"

#include <algorithm>
#include <chrono>

#include "pfx/low_level/rigidbody/pfx_update_rigid_states.h"
#include "pfx/low_level/solver/pfx_correct_joint_positions.h"
#include "pfx/low_level/solver/pfx_solve_constraints.h"

namespace pfx {

namespace {

constexpr PfxUInt32 kNoGroup = 0xffffffffu;

// Times a group's stages one after the other, when the world measures its stages.
class StageClock {
 public:
  using Clock = std::chrono::steady_clock;
  explicit StageClock(bool measures) : m_measures(measures) {
    if (m_measures) m_start = Clock::now();
  }
  // Adds the time since the last stage ended to `seconds`.
  void endStage(double& seconds) {
    if (!m_measures) return;
    const Clock::time_point now = Clock::now();
    seconds += std::chrono::duration<double>(now - m_start).count();
    m_start = now;
  }

 private:
  bool m_measures;
  Clock::time_point m_start;
};

bool touching(const PfxConstraintPair& pair, const PfxContactManifold* manifolds) {
  return pfxGetActive(pair) && manifolds[pfxGetContactId(pair)].getNumContacts() > 0;
}

// Lists the items 0 to numItems - 1 that groupOf(i) gives a group in `indices`, group after
// group, in their order within each, and sets each group's `first` and `count` to where its
// items lie. groupOf is called twice per item.
template <typename Group, typename GroupOf>
void bucketItems(PfxUInt32 numItems, std::vector<Group>& groups, const GroupOf& groupOf,
                 std::vector<PfxUInt32>& indices, std::vector<PfxUInt32>& starts,
                 PfxUInt32 Group::*first, PfxUInt32 Group::*count) {
  const auto numGroups = static_cast<PfxUInt32>(groups.size());
  starts.assign(numGroups + 1, 0);
  for (PfxUInt32 i = 0; i < numItems; ++i) {
    const PfxUInt32 g = groupOf(i);
    if (g != kNoGroup) ++starts[g + 1];
  }
  for (PfxUInt32 g = 0; g < numGroups; ++g) starts[g + 1] += starts[g];
  indices.resize(starts[numGroups]);
  for (PfxUInt32 g = 0; g < numGroups; ++g) {
    groups[g].*first = starts[g];
    groups[g].*count = starts[g + 1] - starts[g];
  }
  for (PfxUInt32 i = 0; i < numItems; ++i) {
    const PfxUInt32 g = groupOf(i);
    if (g != kNoGroup) indices[starts[g]++] = i;
  }
}

}  // namespace

bool PfxIslandGroups::build(const PfxIsland& island, const PfxIslandGroupsWorld& world,
                            PfxUInt32 targetWeight) {
  m_groups.clear();
  const PfxUInt32 numIslands = pfxGetNumIslands(island);
  if (numIslands < 2) return false;

  // Islands in their order, a group closing once it weighs the target.
  m_groupOfBody.assign(world.numRigidBodies, kNoGroup);
  m_localIdOfBody.resize(world.numRigidBodies);
  m_bodyIds.clear();
  PfxUInt32 weight = 0;
  for (PfxUInt32 i = 0; i < numIslands; ++i) {
    PfxUInt32 numBodies = 0, numContacts = 0, numJoints = 0;
    const PfxUInt32* bodies = pfxGetRigidBodiesInIsland(island, i, numBodies);
    pfxGetContactPairsInIsland(island, i, numContacts);
    pfxGetJointsInIsland(island, i, numJoints);
    if (m_groups.empty() || weight >= targetWeight) {
      m_groups.push_back(Group{});
      m_groups.back().firstBody = static_cast<PfxUInt32>(m_bodyIds.size());
      weight = 0;
    }
    Group& group = m_groups.back();
    const PfxUInt32 g = static_cast<PfxUInt32>(m_groups.size() - 1);
    for (PfxUInt32 b = 0; b < numBodies; ++b) {
      m_groupOfBody[bodies[b]] = g;
      m_localIdOfBody[bodies[b]] = group.numOwnBodies++;
      m_bodyIds.push_back(bodies[b]);
    }
    weight += numBodies + numContacts + numJoints;
  }
  if (m_groups.size() < 2) {
    m_groups.clear();
    return false;
  }
  const PfxUInt32 numGroups = static_cast<PfxUInt32>(m_groups.size());

  // Each contact with points, joint and coupling goes to the group of its bodies that
  // impulses move; one between bodies in no island (two fixed bodies) to the first, as the
  // world would still visit it. Islands hold contacts, active joints and couplings whole; one
  // across two groups (which the islands' rules never make) would leave each group a copy of
  // a body the other moves, and the world then solves as a whole. An inactive joint may span
  // two: the solver passes it by.
  bool split = false;
  auto groupOf = [&](PfxUInt32 idA, PfxUInt32 idB, bool acts) {
    const PfxUInt32 a = m_groupOfBody[idA];
    const PfxUInt32 b = m_groupOfBody[idB];
    split = split || (acts && a != kNoGroup && b != kNoGroup && a != b);
    return a != kNoGroup ? a : b != kNoGroup ? b : 0;
  };
  m_contactsInWorld = false;
  std::vector<PfxUInt32>& starts = m_starts;
  bucketItems(
      world.numContactPairs, m_groups,
      [&](PfxUInt32 i) {
        const PfxConstraintPair& pair = world.contactPairs[i];
        if (!touching(pair, world.manifolds)) return kNoGroup;
        m_contactsInWorld = true;
        return groupOf(pfxGetObjectIdA(pair), pfxGetObjectIdB(pair), true);
      },
      m_contactIndices, starts, &Group::firstContact, &Group::numContacts);
  bucketItems(
      world.numJoints, m_groups,
      [&](PfxUInt32 i) {
        const PfxJoint& joint = world.joints[i];
        return groupOf(joint.m_rigidBodyIdA, joint.m_rigidBodyIdB, joint.m_active != 0);
      },
      m_jointIndices, starts, &Group::firstJoint, &Group::numJoints);
  bucketItems(
      world.numCouplings, m_groups,
      [&](PfxUInt32 i) {
        const PfxJointCoupling& coupling = world.couplings[i];
        const PfxJoint& leader = world.joints[coupling.m_leaderJointId];
        const PfxJoint& follower = world.joints[coupling.m_followerJointId];
        const PfxUInt32 g = groupOf(leader.m_rigidBodyIdA, leader.m_rigidBodyIdB, false);
        split = split || g != groupOf(follower.m_rigidBodyIdA, follower.m_rigidBodyIdB, false);
        return g;
      },
      m_couplingIndices, starts, &Group::firstCoupling, &Group::numCouplings);
  if (split) {
    m_groups.clear();
    return false;
  }
  // Couplings name their joints by world id; only a world with couplings needs the map.
  if (world.numCouplings > 0) m_localJointOf.resize(world.numJoints);
  for (const Group& group : m_groups) {
    if (group.numCouplings == 0) continue;
    for (PfxUInt32 k = 0; k < group.numJoints; ++k) {
      m_localJointOf[m_jointIndices[group.firstJoint + k]] = k;
    }
  }

  // The bodies of other groups and of none that a group's pairs name, after its own, by id;
  // the groups' bodies are laid out again group after group.
  std::vector<PfxUInt32>& ownIds = m_ownIds;
  ownIds.swap(m_bodyIds);
  m_bodyIds.clear();
  PfxUInt32 totalWeight = 0;
  for (PfxUInt32 g = 0; g < numGroups; ++g) {
    Group& group = m_groups[g];
    const PfxUInt32 ownBegin = group.firstBody;
    group.firstBody = static_cast<PfxUInt32>(m_bodyIds.size());
    m_bodyIds.insert(m_bodyIds.end(), ownIds.begin() + ownBegin,
                     ownIds.begin() + ownBegin + group.numOwnBodies);
    auto addForeign = [&](PfxUInt32 idA, PfxUInt32 idB) {
      if (m_groupOfBody[idA] != g) m_bodyIds.push_back(idA);
      if (m_groupOfBody[idB] != g) m_bodyIds.push_back(idB);
    };
    for (PfxUInt32 k = 0; k < group.numContacts; ++k) {
      const PfxConstraintPair& pair = world.contactPairs[m_contactIndices[group.firstContact + k]];
      addForeign(pfxGetObjectIdA(pair), pfxGetObjectIdB(pair));
    }
    for (PfxUInt32 k = 0; k < group.numJoints; ++k) {
      const PfxJoint& joint = world.joints[m_jointIndices[group.firstJoint + k]];
      addForeign(joint.m_rigidBodyIdA, joint.m_rigidBodyIdB);
    }
    const auto foreignBegin = m_bodyIds.begin() + group.firstBody + group.numOwnBodies;
    std::sort(foreignBegin, m_bodyIds.end());
    m_bodyIds.erase(std::unique(foreignBegin, m_bodyIds.end()), m_bodyIds.end());
    group.numBodies = static_cast<PfxUInt32>(m_bodyIds.size()) - group.firstBody;
    totalWeight += group.numBodies + group.numContacts + group.numJoints;
  }
  // A group that alone weighs a good share of the world also runs its stages' loops on the
  // threads, so that one large island does not leave them idle.
  for (Group& group : m_groups) {
    group.threaded = group.numBodies + group.numContacts + group.numJoints >= totalWeight / 4;
  }
  m_states.resize(m_bodyIds.size());
  m_bodies.resize(m_bodyIds.size());
  m_solverBodies.resize(m_bodyIds.size());
  m_contactPairs.resize(m_contactIndices.size());
  m_jointPairs.resize(m_jointIndices.size());
  m_joints.resize(m_jointIndices.size());
  m_couplings.resize(m_couplingIndices.size());
  m_results.resize(numGroups);
  m_workContactTreeNodes = 0;
  return true;
}

PfxUInt32 PfxIslandGroups::localId(const Group& group, PfxUInt32 groupIndex,
                                   PfxUInt32 rigidBodyId) const {
  if (m_groupOfBody[rigidBodyId] == groupIndex) return m_localIdOfBody[rigidBodyId];
  const auto foreignBegin = m_bodyIds.begin() + group.firstBody + group.numOwnBodies;
  const auto foreignEnd = m_bodyIds.begin() + group.firstBody + group.numBodies;
  return group.numOwnBodies +
         static_cast<PfxUInt32>(std::lower_bound(foreignBegin, foreignEnd, rigidBodyId) -
                                foreignBegin);
}

void PfxIslandGroups::layOutWork(PfxUInt32 contactTreeNodes) {
  std::size_t offset = 0;
  for (Group& group : m_groups) {
    const PfxUInt32 nodes = std::min(
        contactTreeNodes, group.numBodies + std::min(group.numBodies, group.numContacts));
    const std::size_t bytes = std::max<std::size_t>(
        pfxGetWorkBytesOfSolveConstraints(group.numBodies, group.numContacts, group.numJoints, 1,
                                          nodes),
        pfxGetWorkBytesOfCorrectJointPositions(group.numBodies, group.numJoints,
                                               group.numContacts));
    group.workOffset = offset;
    group.workBytes = bytes;
    offset += (bytes + sizeof(PfxSortData16) - 1) / sizeof(PfxSortData16);
  }
  if (m_work.size() < offset) m_work.resize(offset);
  m_workContactTreeNodes = contactTreeNodes;
}

PfxInt32 PfxIslandGroups::solveGroup(PfxUInt32 groupIndex, const PfxIslandGroupsWorld& world,
                                     Result& result, PfxTaskManager* taskManager) {
  const Group& group = m_groups[groupIndex];
  PfxRigidState* const states = m_states.data() + group.firstBody;
  PfxRigidBody* const bodies = m_bodies.data() + group.firstBody;
  PfxSolverBody* const solverBodies = m_solverBodies.data() + group.firstBody;
  for (PfxUInt32 i = 0; i < group.numBodies; ++i) {
    const PfxUInt32 id = m_bodyIds[group.firstBody + i];
    states[i] = world.states[id];
    bodies[i] = world.bodies[id];
    solverBodies[i] = world.solverBodies[id];
  }
  auto renumber = [&](PfxConstraintPair pair) {
    pair.key = pfxCreatePairKey(localId(group, groupIndex, pfxGetObjectIdA(pair)),
                                localId(group, groupIndex, pfxGetObjectIdB(pair)));
    return pair;
  };
  PfxConstraintPair* const contactPairs = m_contactPairs.data() + group.firstContact;
  for (PfxUInt32 k = 0; k < group.numContacts; ++k) {
    contactPairs[k] = renumber(world.contactPairs[m_contactIndices[group.firstContact + k]]);
  }
  PfxConstraintPair* const jointPairs = m_jointPairs.data() + group.firstJoint;
  for (PfxUInt32 k = 0; k < group.numJoints; ++k) {
    jointPairs[k] = renumber(world.jointPairs[m_jointIndices[group.firstJoint + k]]);
  }
  // With couplings, the group's joints and couplings as copies numbered as the group is.
  PfxJoint* joints = world.joints;
  PfxUInt32 numJoints = world.numJoints;
  PfxJointCoupling* const couplings = m_couplings.data() + group.firstCoupling;
  if (group.numCouplings > 0) {
    joints = m_joints.data() + group.firstJoint;
    numJoints = group.numJoints;
    for (PfxUInt32 k = 0; k < group.numJoints; ++k) {
      joints[k] = world.joints[m_jointIndices[group.firstJoint + k]];
      joints[k].m_rigidBodyIdA = localId(group, groupIndex, joints[k].m_rigidBodyIdA);
      joints[k].m_rigidBodyIdB = localId(group, groupIndex, joints[k].m_rigidBodyIdB);
      pfxSetConstraintId(jointPairs[k], k);
    }
    for (PfxUInt32 k = 0; k < group.numCouplings; ++k) {
      PfxJointCoupling& coupling = couplings[k];
      coupling = world.couplings[m_couplingIndices[group.firstCoupling + k]];
      coupling.m_leaderJointId = m_localJointOf[coupling.m_leaderJointId];
      coupling.m_followerJointId = m_localJointOf[coupling.m_followerJointId];
      for (PfxUInt32 b = 0; b < coupling.m_numBodies; ++b) {
        coupling.m_bodies[b].m_rigidBodyId =
            localId(group, groupIndex, coupling.m_bodies[b].m_rigidBodyId);
      }
    }
  }
  PfxTaskManager* const stageTasks = group.threaded ? taskManager : nullptr;
  void* const work = m_work.data() + group.workOffset;
  const auto workBytes = static_cast<PfxUInt32>(group.workBytes);

  StageClock clock(world.measureStages);
  PfxSolveConstraintsParam solve;
  solve.workBuff = work;
  solve.workBytes = workBytes;
  solve.contactPairs = contactPairs;
  solve.numContactPairs = group.numContacts;
  solve.offsetContactManifolds = world.manifolds;
  solve.numContactManifolds = world.numManifolds;
  solve.jointPairs = jointPairs;
  solve.numJointPairs = group.numJoints;
  solve.offsetJoints = joints;
  solve.numJoints = numJoints;
  solve.offsetJointCouplings = couplings;
  solve.numJointCouplings = group.numCouplings;
  solve.offsetRigidStates = states;
  solve.offsetSolverBodies = solverBodies;
  solve.numRigidBodies = group.numBodies;
  solve.iteration = world.iteration;
  solve.timeStep = world.timeStep;
  solve.restitutionThreshold = world.restitutionThreshold;
  solve.gravity = world.shockGravity;
  solve.outContactTreeNodes = &result.contactTreeNodes;
  if (const PfxInt32 err = pfxSolveConstraints(solve, stageTasks); err != PFX_OK) return err;
  clock.endStage(result.seconds[0]);

  PfxUpdateRigidStatesParam integrate;
  integrate.states = states;
  integrate.bodies = bodies;
  integrate.numRigidBodies = group.numBodies;
  integrate.timeStep = world.timeStep;
  if (const PfxInt32 err = pfxUpdateRigidStates(integrate, stageTasks); err != PFX_OK) return err;
  clock.endStage(result.seconds[1]);

  if (group.numJoints > 0) {
    PfxCorrectJointPositionsParam correct;
    correct.workBuff = work;
    correct.workBytes = workBytes;
    correct.jointPairs = jointPairs;
    correct.numJointPairs = group.numJoints;
    correct.offsetJoints = joints;
    correct.numJoints = numJoints;
    correct.offsetJointCouplings = couplings;
    correct.numJointCouplings = group.numCouplings;
    correct.contactPairs = contactPairs;
    correct.numContactPairs = group.numContacts;
    correct.offsetContactManifolds = world.manifolds;
    correct.numContactManifolds = world.numManifolds;
    correct.contactPassAnyway = m_contactsInWorld;
    correct.offsetRigidStates = states;
    correct.offsetRigidBodies = bodies;
    correct.offsetSolverBodies = solverBodies;
    correct.numRigidBodies = group.numBodies;
    correct.timeStep = world.timeStep;
    correct.iteration = world.iteration;
    if (const PfxInt32 err = pfxCorrectJointPositions(correct, stageTasks); err != PFX_OK) {
      return err;
    }
    clock.endStage(result.seconds[2]);
  }
  for (PfxUInt32 i = 0; i < group.numOwnBodies; ++i) {
    world.states[m_bodyIds[group.firstBody + i]] = states[i];
  }
  if (group.numCouplings > 0) {
    const PfxUInt32* const bodyIds = m_bodyIds.data() + group.firstBody;
    for (PfxUInt32 k = 0; k < group.numJoints; ++k) {
      PfxJoint& joint = world.joints[m_jointIndices[group.firstJoint + k]];
      const PfxUInt32 idA = joint.m_rigidBodyIdA, idB = joint.m_rigidBodyIdB;
      joint = joints[k];
      joint.m_rigidBodyIdA = idA;
      joint.m_rigidBodyIdB = idB;
    }
    for (PfxUInt32 k = 0; k < group.numCouplings; ++k) {
      PfxJointCoupling& coupling = world.couplings[m_couplingIndices[group.firstCoupling + k]];
      const PfxUInt32 leader = coupling.m_leaderJointId, follower = coupling.m_followerJointId;
      coupling = couplings[k];
      coupling.m_leaderJointId = leader;
      coupling.m_followerJointId = follower;
      for (PfxUInt32 b = 0; b < coupling.m_numBodies; ++b) {
        coupling.m_bodies[b].m_rigidBodyId = bodyIds[coupling.m_bodies[b].m_rigidBodyId];
      }
    }
  }
  return PFX_OK;
}

PfxInt32 PfxIslandGroups::solve(const PfxIslandGroupsWorld& world, PfxUInt32& contactTreeNodes,
                                PfxWorldStats& stats, PfxTaskManager* taskManager) {
  if (m_workContactTreeNodes != contactTreeNodes) layOutWork(contactTreeNodes);
  const auto numGroups = static_cast<PfxUInt32>(m_groups.size());
  for (Result& result : m_results) result = Result{};
  auto solveGroups = [&](auto&& wanted) {
    pfxParallelFor(taskManager, numGroups, 1, [&](PfxUInt32 begin, PfxUInt32 end) {
      for (PfxUInt32 g = begin; g < end; ++g) {
        if (wanted(g)) m_results[g].err = solveGroup(g, world, m_results[g], taskManager);
      }
    });
  };
  solveGroups([](PfxUInt32) { return true; });
  // A contacts' tree larger than any before, in groups that have written nothing: room for
  // it and a quarter more, as the world gives, and those groups again.
  PfxUInt32 largestTree = 0;
  for (const Result& result : m_results) {
    if (result.err == PFX_ERR_OUT_OF_BUFFER) {
      largestTree = std::max(largestTree, result.contactTreeNodes);
    }
  }
  if (largestTree > contactTreeNodes) {
    contactTreeNodes = largestTree + largestTree / 4;
    layOutWork(contactTreeNodes);
    solveGroups([&](PfxUInt32 g) { return m_results[g].err == PFX_ERR_OUT_OF_BUFFER; });
  }
  PfxInt32 err = PFX_OK;
  for (const Result& result : m_results) {
    stats.stageSeconds[kPfxStageSolveConstraints] += result.seconds[0];
    stats.stageSeconds[kPfxStageUpdateRigidStates] += result.seconds[1];
    stats.stageSeconds[kPfxStageCorrectJointPositions] += result.seconds[2];
    if (err == PFX_OK) err = result.err;
  }
  return err;
}

}  // namespace pfx
