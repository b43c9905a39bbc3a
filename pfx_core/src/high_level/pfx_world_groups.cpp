// PfxWorld's solve a group of islands at a time (pfx_island_groups.h).
#include <algorithm>

#include "high_level/pfx_island_groups.h"
#include "pfx/high_level/pfx_world.h"

namespace pfx {

namespace {

// Groups of a share of the world's bodies, contacts and joints, a few per thread, so that
// the threads share them out evenly: more groups balance better, fewer cost less to set up.
// None lighter than an arm and a half: four arms with a ragdoll, in groups of at least 64,
// made one group too large for the other to balance (two threads 5 % slower than one); in
// groups of at least 32, two threads took 0.76 of one's time.
constexpr PfxUInt32 kGroupsPerThread = 8;
constexpr PfxUInt32 kMinGroupWeight = 32;

}  // namespace

PfxIslandGroupsWorld PfxWorld::islandGroupsWorld() {
  PfxIslandGroupsWorld world;
  world.states = m_states.data();
  world.bodies = m_bodies.data();
  world.solverBodies = m_solverBodies.data();
  world.numRigidBodies = getNumRigidBodies();
  world.contactPairs = m_pairs.data();
  world.numContactPairs = m_numPairs;
  world.manifolds = m_manifolds.data();
  world.numManifolds = static_cast<PfxUInt32>(m_manifolds.size());
  world.jointPairs = m_jointPairs.data();
  world.joints = m_joints.data();
  world.numJoints = getNumJoints();
  world.couplings = m_jointCouplings.data();
  world.numCouplings = getNumJointCouplings();
  return world;
}

bool PfxWorld::buildIslandGroups() {
  // On one thread the world solves as a whole: a group at a time would only add the cost of
  // copying its bodies.
  m_stats.numIslandGroups = 0;
  const PfxUInt32 numThreads = m_taskManager.getNumThreads();
  if (numThreads < 2 || !m_island) return false;
  if (!m_islandGroups) m_islandGroups = std::make_unique<PfxIslandGroups>();
  const PfxIslandGroupsWorld world = islandGroupsWorld();
  const PfxUInt32 weight = getNumRigidBodies() + m_numPairs + getNumJoints();
  if (!m_islandGroups->build(*m_island, world,
                             std::max(kMinGroupWeight, weight / (numThreads * kGroupsPerThread)))) {
    return false;
  }
  m_stats.numIslandGroups = m_islandGroups->numGroups();
  return true;
}

PfxInt32 PfxWorld::solveIslandGroups(PfxFloat timeStep) {
  PfxIslandGroupsWorld world = islandGroupsWorld();
  world.timeStep = timeStep;
  world.iteration = m_param.iteration;
  world.restitutionThreshold = m_param.restitutionThreshold;
  world.measureStages = m_param.measureStages;
  // A world with joints takes no shock propagation (pfxSolveConstraints), and neither do
  // its groups without joints.
  if (m_param.enableShockPropagation && getNumJoints() == 0) world.shockGravity = m_param.gravity;
  return m_islandGroups->solve(world, m_contactTreeNodes, m_stats, &m_taskManager);
}

}  // namespace pfx
