// pfxGenerateIsland (seed chapter 2, "Simulation Island"): islands against a brute-force
// connected-components reference on random graphs, numbering independent of the order of
// the links, fixed and keyframe bodies joining no two islands, and bad input rejected with
// nothing written. Also what the seed says of the other stages and sleeping bodies: forces,
// the solver bodies and joint pairs leave them alone.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "pfx/base_level/joint/pfx_joint_init.h"
#include "pfx/low_level/rigidbody/pfx_apply_external_force.h"
#include "pfx/low_level/solver/pfx_island_generation.h"
#include "pfx/low_level/solver/pfx_setup_solver_bodies.h"

using namespace pfx;

namespace {

struct RandomGraph {
  std::vector<PfxRigidState> states;
  std::vector<PfxConstraintPair> pairs;
  std::vector<PfxJoint> joints;
  std::vector<PfxJointCoupling> couplings;
};

RandomGraph makeRandomGraph(std::mt19937& rng, PfxUInt32 numBodies, PfxUInt32 numPairs,
                            PfxUInt32 numJoints, PfxUInt32 numCouplings) {
  RandomGraph g;
  std::uniform_int_distribution<int> type(0, 19);
  std::uniform_int_distribution<PfxUInt32> body(0, numBodies - 1);
  std::bernoulli_distribution often(0.85);
  g.states.resize(numBodies);
  for (PfxUInt32 i = 0; i < numBodies; ++i) {
    g.states[i].reset();
    g.states[i].setRigidBodyId(i);
    const int t = type(rng);
    g.states[i].setMotionType(t < 2   ? kPfxMotionTypeFixed
                              : t < 3 ? kPfxMotionTypeKeyframe
                              : t < 4 ? kPfxMotionTypeTrigger
                              : t < 6 ? kPfxMotionTypeOneWay
                                      : kPfxMotionTypeActive);
  }
  for (PfxUInt32 p = 0; p < numPairs; ++p) {
    PfxUInt32 a = body(rng), b = body(rng);
    if (a == b) b = (a + 1) % numBodies;
    PfxConstraintPair pair;
    pfxInitializePair(pair, a, g.states[a].getMotionType(), b, g.states[b].getMotionType());
    pfxSetContactId(pair, p);
    pfxSetNumConstraints(pair, often(rng) ? 1 + p % 4 : 0);
    g.pairs.push_back(pair);
  }
  for (PfxUInt32 j = 0; j < numJoints; ++j) {
    PfxJoint joint;
    std::memset(static_cast<void*>(&joint), 0, sizeof(joint));
    joint.m_rigidBodyIdA = body(rng);
    joint.m_rigidBodyIdB = body(rng);
    joint.m_active = often(rng) ? 1 : 0;
    g.joints.push_back(joint);
  }
  std::uniform_int_distribution<PfxUInt32> jointId(0, numJoints - 1);
  for (PfxUInt32 c = 0; c < numCouplings; ++c) {
    PfxJointCoupling coupling;
    coupling.reset();
    coupling.m_leaderJointId = jointId(rng);
    coupling.m_followerJointId = jointId(rng);
    coupling.m_active = often(rng) ? 1 : 0;
    g.couplings.push_back(coupling);
  }
  return g;
}

bool dynamicBody(const PfxRigidState& s) { return pfxMotionTypeIsDynamic(s.getMotionType()); }

// Connected components by breadth-first search over an adjacency list, labelled by their
// lowest body; -1 for fixed bodies.
std::vector<long> referenceComponents(const RandomGraph& g) {
  const std::size_t n = g.states.size();
  std::vector<std::vector<PfxUInt32>> adjacent(n);
  auto link = [&](PfxUInt32 a, PfxUInt32 b) {
    if (dynamicBody(g.states[a]) && dynamicBody(g.states[b])) {
      adjacent[a].push_back(b);
      adjacent[b].push_back(a);
    }
  };
  for (const PfxConstraintPair& pair : g.pairs) {
    if (pfxGetActive(pair) && pfxGetNumConstraints(pair) > 0) {
      link(pfxGetObjectIdA(pair), pfxGetObjectIdB(pair));
    }
  }
  for (const PfxJoint& joint : g.joints) {
    if (joint.m_active) link(joint.m_rigidBodyIdA, joint.m_rigidBodyIdB);
  }
  for (const PfxJointCoupling& coupling : g.couplings) {
    if (!coupling.m_active) continue;
    const PfxJoint& l = g.joints[coupling.m_leaderJointId];
    const PfxJoint& f = g.joints[coupling.m_followerJointId];
    const PfxUInt32 ids[4] = {l.m_rigidBodyIdA, l.m_rigidBodyIdB, f.m_rigidBodyIdA, f.m_rigidBodyIdB};
    for (PfxUInt32 a : ids) {
      for (PfxUInt32 b : ids) link(a, b);
    }
  }
  std::vector<long> label(n, -2);
  for (std::size_t start = 0; start < n; ++start) {
    if (g.states[start].getMotionType() == kPfxMotionTypeFixed) {
      label[start] = -1;
      continue;
    }
    if (label[start] != -2) continue;
    std::vector<PfxUInt32> queue{PfxUInt32(start)};
    label[start] = long(start);
    for (std::size_t q = 0; q < queue.size(); ++q) {
      for (PfxUInt32 next : adjacent[queue[q]]) {
        if (label[next] == -2) {
          label[next] = long(start);
          queue.push_back(next);
        }
      }
    }
  }
  return label;
}

struct IslandBuffer {
  std::vector<PfxSortData16> storage;
  PfxGenerateIslandParam param;
  explicit IslandBuffer(const RandomGraph& g) {
    const PfxUInt32 bytes =
        pfxGetIslandBytes(PfxUInt32(g.states.size()), PfxUInt32(g.pairs.size()),
                          PfxUInt32(g.joints.size()));
    storage.resize(bytes / sizeof(PfxSortData16) + 1);
    param.islandBuff = storage.data();
    param.islandBytes = bytes;
    param.offsetRigidStates = g.states.data();
    param.numRigidBodies = PfxUInt32(g.states.size());
    param.contactPairs = g.pairs.data();
    param.numContactPairs = PfxUInt32(g.pairs.size());
    param.offsetJoints = g.joints.data();
    param.numJoints = PfxUInt32(g.joints.size());
    param.offsetJointCouplings = g.couplings.data();
    param.numJointCouplings = PfxUInt32(g.couplings.size());
  }
};

// The island's bodies, pairs and joints as plain lists, for comparing two generations.
struct IslandLists {
  std::vector<PfxUInt32> islandOf;
  std::vector<std::vector<PfxUInt32>> bodies, joints;
  std::vector<std::vector<PfxUInt64>> pairKeys;
};

IslandLists listsOf(const PfxIsland& island, PfxUInt32 numBodies) {
  IslandLists lists;
  for (PfxUInt32 i = 0; i < numBodies; ++i) lists.islandOf.push_back(pfxGetIslandId(island, i));
  for (PfxUInt32 k = 0; k < pfxGetNumIslands(island); ++k) {
    PfxUInt32 count = 0;
    const PfxUInt32* bodies = pfxGetRigidBodiesInIsland(island, k, count);
    lists.bodies.emplace_back(bodies, bodies + count);
    const PfxUInt32* joints = pfxGetJointsInIsland(island, k, count);
    lists.joints.emplace_back(joints, joints + count);
    const PfxConstraintPair* pairs = pfxGetContactPairsInIsland(island, k, count);
    lists.pairKeys.emplace_back();
    for (PfxUInt32 p = 0; p < count; ++p) lists.pairKeys.back().push_back(pairs[p].key);
  }
  return lists;
}

}  // namespace

TEST(IslandGeneration, MatchesConnectedComponentsOfRandomGraphs) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 40; ++trial) {
    const PfxUInt32 numBodies = 2 + trial * 7;
    const RandomGraph g = makeRandomGraph(rng, numBodies, numBodies + trial * 3, 1 + trial / 4,
                                          trial % 5);
    IslandBuffer buffer(g);
    PfxGenerateIslandResult result;
    ASSERT_EQ(pfxGenerateIsland(buffer.param, result), PFX_OK);
    const PfxIsland& island = *result.island;
    ASSERT_EQ(pfxGetNumIslands(island), result.numIslands);
    const std::vector<long> label = referenceComponents(g);

    // Same partition, numbered by lowest body id.
    std::vector<long> roots;
    for (PfxUInt32 i = 0; i < numBodies; ++i) {
      if (label[i] == long(i)) roots.push_back(label[i]);
    }
    ASSERT_EQ(result.numIslands, roots.size()) << "trial " << trial;
    for (PfxUInt32 i = 0; i < numBodies; ++i) {
      const PfxUInt32 k = pfxGetIslandId(island, i);
      if (label[i] < 0) {
        EXPECT_EQ(k, PFX_ISLAND_NONE);
        continue;
      }
      const long expected = std::lower_bound(roots.begin(), roots.end(), label[i]) - roots.begin();
      EXPECT_EQ(long(k), expected) << "trial " << trial << " body " << i;
    }
    // Each island lists exactly its bodies, ascending; its pairs and joints are those
    // with points (or active) and a body that forces move, under that body's island.
    PfxUInt32 listedBodies = 0, listedPairs = 0, listedJoints = 0;
    for (PfxUInt32 k = 0; k < result.numIslands; ++k) {
      PfxUInt32 count = 0;
      const PfxUInt32* bodies = pfxGetRigidBodiesInIsland(island, k, count);
      ASSERT_GT(count, 0u);
      EXPECT_EQ(bodies[0], PfxUInt32(roots[k]));
      for (PfxUInt32 b = 0; b < count; ++b) {
        EXPECT_EQ(pfxGetIslandId(island, bodies[b]), k);
        if (b > 0) {
          EXPECT_LT(bodies[b - 1], bodies[b]);
        }
      }
      listedBodies += count;
      const PfxConstraintPair* pairs = pfxGetContactPairsInIsland(island, k, count);
      for (PfxUInt32 p = 0; p < count; ++p) {
        const PfxUInt32 a = pfxGetObjectIdA(pairs[p]), b = pfxGetObjectIdB(pairs[p]);
        EXPECT_TRUE(pfxGetNumConstraints(pairs[p]) > 0 && pfxGetActive(pairs[p]));
        const PfxUInt32 owner = dynamicBody(g.states[a]) ? a : b;
        EXPECT_TRUE(dynamicBody(g.states[owner]));
        EXPECT_EQ(pfxGetIslandId(island, owner), k);
        if (p > 0) {
          EXPECT_LT(pfxGetContactId(pairs[p - 1]), pfxGetContactId(pairs[p]));
        }
      }
      listedPairs += count;
      const PfxUInt32* joints = pfxGetJointsInIsland(island, k, count);
      for (PfxUInt32 j = 0; j < count; ++j) {
        const PfxJoint& joint = g.joints[joints[j]];
        EXPECT_TRUE(joint.m_active);
        const PfxUInt32 owner =
            dynamicBody(g.states[joint.m_rigidBodyIdA]) ? joint.m_rigidBodyIdA : joint.m_rigidBodyIdB;
        EXPECT_EQ(pfxGetIslandId(island, owner), k);
      }
      listedJoints += count;
    }
    PfxUInt32 movingBodies = 0, expectedPairs = 0, expectedJoints = 0;
    for (const PfxRigidState& s : g.states) movingBodies += s.getMotionType() != kPfxMotionTypeFixed;
    for (const PfxConstraintPair& pair : g.pairs) {
      expectedPairs += pfxGetActive(pair) && pfxGetNumConstraints(pair) > 0 &&
                       (dynamicBody(g.states[pfxGetObjectIdA(pair)]) ||
                        dynamicBody(g.states[pfxGetObjectIdB(pair)]));
    }
    for (const PfxJoint& joint : g.joints) {
      expectedJoints += joint.m_active && (dynamicBody(g.states[joint.m_rigidBodyIdA]) ||
                                           dynamicBody(g.states[joint.m_rigidBodyIdB]));
    }
    EXPECT_EQ(listedBodies, movingBodies);
    EXPECT_EQ(listedPairs, expectedPairs);
    EXPECT_EQ(listedJoints, expectedJoints);
  }
}

TEST(IslandGeneration, NumberingDependsOnlyOnTheLinksNotTheirOrder) {
  std::mt19937 rng(11);
  RandomGraph g = makeRandomGraph(rng, 300, 500, 40, 6);
  IslandBuffer first(g);
  PfxGenerateIslandResult result;
  ASSERT_EQ(pfxGenerateIsland(first.param, result), PFX_OK);
  const IslandLists before = listsOf(*result.island, 300);
  ASSERT_GT(result.numIslands, 10u);

  // Shuffled pairs: same islands, same bodies; each island's pairs the same set.
  RandomGraph shuffled = g;
  std::shuffle(shuffled.pairs.begin(), shuffled.pairs.end(), rng);
  IslandBuffer second(shuffled);
  ASSERT_EQ(pfxGenerateIsland(second.param, result), PFX_OK);
  const IslandLists after = listsOf(*result.island, 300);
  EXPECT_EQ(after.islandOf, before.islandOf);
  EXPECT_EQ(after.bodies, before.bodies);
  EXPECT_EQ(after.joints, before.joints);
  ASSERT_EQ(after.pairKeys.size(), before.pairKeys.size());
  for (std::size_t k = 0; k < before.pairKeys.size(); ++k) {
    std::vector<PfxUInt64> a = before.pairKeys[k], b = after.pairKeys[k];
    std::sort(a.begin(), a.end());
    std::sort(b.begin(), b.end());
    EXPECT_EQ(a, b);
  }
}

TEST(IslandGeneration, FixedAndKeyframeBodiesJoinNoTwoIslands) {
  // Bodies 0 fixed, 1 keyframe, 2..5 active: 2 and 3 both touch the fixed body and the
  // keyframe body, 4 and 5 touch each other.
  RandomGraph g;
  g.states.resize(6);
  for (PfxUInt32 i = 0; i < 6; ++i) {
    g.states[i].reset();
    g.states[i].setRigidBodyId(i);
  }
  g.states[0].setMotionType(kPfxMotionTypeFixed);
  g.states[1].setMotionType(kPfxMotionTypeKeyframe);
  const PfxUInt32 links[][2] = {{0, 2}, {0, 3}, {1, 2}, {1, 3}, {4, 5}};
  for (const auto& l : links) {
    PfxConstraintPair pair;
    pfxInitializePair(pair, l[0], g.states[l[0]].getMotionType(), l[1], g.states[l[1]].getMotionType());
    pfxSetNumConstraints(pair, 2);
    g.pairs.push_back(pair);
  }
  IslandBuffer buffer(g);
  PfxGenerateIslandResult result;
  ASSERT_EQ(pfxGenerateIsland(buffer.param, result), PFX_OK);
  const PfxIsland& island = *result.island;
  EXPECT_EQ(result.numIslands, 4u);  // {1}, {2}, {3}, {4, 5}
  EXPECT_EQ(pfxGetIslandId(island, 0), PFX_ISLAND_NONE);
  EXPECT_EQ(pfxGetIslandId(island, 1), 0u);
  EXPECT_EQ(pfxGetIslandId(island, 2), 1u);
  EXPECT_EQ(pfxGetIslandId(island, 3), 2u);
  EXPECT_EQ(pfxGetIslandId(island, 4), 3u);
  EXPECT_EQ(pfxGetIslandId(island, 5), 3u);
  PfxUInt32 count = 0;
  pfxGetContactPairsInIsland(island, 1, count);
  EXPECT_EQ(count, 2u);  // body 2 with the fixed and with the keyframe body
  pfxGetContactPairsInIsland(island, 0, count);
  EXPECT_EQ(count, 0u);
  // Queries out of range.
  EXPECT_EQ(pfxGetIslandId(island, 6), PFX_ISLAND_NONE);
  EXPECT_EQ(pfxGetRigidBodiesInIsland(island, 4, count), nullptr);
  EXPECT_EQ(count, 0u);
  EXPECT_EQ(pfxGetJointsInIsland(island, 99, count), nullptr);
  EXPECT_EQ(pfxGetContactPairsInIsland(island, PFX_ISLAND_NONE, count), nullptr);
  EXPECT_EQ(pfxGetIslandBytes(0xffffffffu, 0xffffffffu, 0), 0xffffffffu);
}

TEST(IslandGeneration, BadInputIsRejectedAndWritesNothing) {
  std::mt19937 rng(3);
  const RandomGraph good = makeRandomGraph(rng, 20, 30, 4, 2);
  struct Case {
    const char* what;
    void (*spoil)(RandomGraph&, PfxGenerateIslandParam&);
    PfxInt32 expected;
  };
  const Case cases[] = {
      {"null states", [](RandomGraph&, PfxGenerateIslandParam& p) { p.offsetRigidStates = nullptr; },
       PFX_ERR_NULL_POINTER},
      {"null pairs", [](RandomGraph&, PfxGenerateIslandParam& p) { p.contactPairs = nullptr; },
       PFX_ERR_NULL_POINTER},
      {"null joints", [](RandomGraph&, PfxGenerateIslandParam& p) { p.offsetJoints = nullptr; },
       PFX_ERR_NULL_POINTER},
      {"null couplings",
       [](RandomGraph&, PfxGenerateIslandParam& p) { p.offsetJointCouplings = nullptr; },
       PFX_ERR_NULL_POINTER},
      {"null buffer", [](RandomGraph&, PfxGenerateIslandParam& p) { p.islandBuff = nullptr; },
       PFX_ERR_OUT_OF_BUFFER},
      {"small buffer", [](RandomGraph&, PfxGenerateIslandParam& p) { p.islandBytes -= 32; },
       PFX_ERR_OUT_OF_BUFFER},
      {"misaligned buffer",
       [](RandomGraph&, PfxGenerateIslandParam& p) {
         p.islandBuff = static_cast<char*>(p.islandBuff) + 4;
         p.islandBytes -= 16;
       },
       PFX_ERR_INVALID_ALIGNMENT},
      {"buffer over the pairs",
       [](RandomGraph& g, PfxGenerateIslandParam& p) {
         p.islandBuff = g.pairs.data();
         p.islandBytes = 1u << 30;
       },
       PFX_ERR_INVALID_VALUE},
      {"pair body out of range",
       [](RandomGraph& g, PfxGenerateIslandParam&) {
         pfxInitializePair(g.pairs[5], 3, kPfxMotionTypeActive, 20, kPfxMotionTypeActive);
       },
       PFX_ERR_OUT_OF_RANGE},
      {"joint body out of range",
       [](RandomGraph& g, PfxGenerateIslandParam&) { g.joints[1].m_rigidBodyIdB = 20; },
       PFX_ERR_OUT_OF_RANGE},
      {"coupling joint out of range",
       [](RandomGraph& g, PfxGenerateIslandParam&) { g.couplings[0].m_followerJointId = 4; },
       PFX_ERR_OUT_OF_RANGE},
  };
  for (const Case& c : cases) {
    RandomGraph g = good;
    IslandBuffer buffer(g);
    std::memset(static_cast<void*>(buffer.storage.data()), 0xab,
                buffer.storage.size() * sizeof(PfxSortData16));
    const std::vector<PfxSortData16> before = buffer.storage;
    const std::vector<PfxConstraintPair> pairsBefore = g.pairs;
    c.spoil(g, buffer.param);
    PfxGenerateIslandResult result;
    result.numIslands = 1234;
    EXPECT_EQ(pfxGenerateIsland(buffer.param, result), c.expected) << c.what;
    EXPECT_EQ(result.numIslands, 1234u) << c.what;
    EXPECT_EQ(result.island, nullptr) << c.what;
    EXPECT_EQ(std::memcmp(before.data(), buffer.storage.data(),
                          before.size() * sizeof(PfxSortData16)),
              0)
        << c.what;
    if (std::string(c.what) == "buffer over the pairs") {
      EXPECT_EQ(std::memcmp(pairsBefore.data(), g.pairs.data(),
                            g.pairs.size() * sizeof(PfxConstraintPair)),
                0);
    }
  }
}

// The seed: the stages leave sleeping bodies alone, and the solver has nothing to do with a
// joint between sleeping (or sleeping and fixed) bodies.
TEST(IslandGeneration, LowLevelStagesLeaveSleepingBodiesAlone) {
  PfxRigidState states[2];
  PfxRigidBody bodies[2];
  for (int i = 0; i < 2; ++i) {
    states[i].reset();
    states[i].setRigidBodyId(i);
    states[i].setLinearVelocity(PfxVector3(1, 0, 0));
    bodies[i].reset();
    bodies[i].setMass(2);
    bodies[i].setInertia(PfxMatrix3::Identity());
  }
  states[1].sleep();
  PfxApplyExternalForceParam force;
  force.states = states;
  force.bodies = bodies;
  force.numRigidBodies = 2;
  force.gravity = PfxVector3(0, -8, 0);
  force.timeStep = 0.125f;
  ASSERT_EQ(pfxApplyExternalForce(force), PFX_OK);
  EXPECT_EQ(states[0].getLinearVelocity(), PfxVector3(1, -1, 0));
  EXPECT_EQ(states[1].getLinearVelocity(), PfxVector3(1, 0, 0));

  PfxSolverBody solverBodies[2];
  PfxSetupSolverBodiesParam setup;
  setup.states = states;
  setup.bodies = bodies;
  setup.solverBodies = solverBodies;
  setup.numRigidBodies = 2;
  ASSERT_EQ(pfxSetupSolverBodies(setup), PFX_OK);
  EXPECT_EQ(solverBodies[0].m_massInv, 0.5f);
  EXPECT_EQ(solverBodies[1].m_massInv, 0.0f);
  EXPECT_TRUE(solverBodies[1].m_inertiaInv.isZero(0));

  PfxJoint joint;
  PfxBallJointInitParam ball;
  ASSERT_EQ(pfxInitializeBallJoint(joint, states[0], states[1], ball), PFX_OK);
  PfxConstraintPair pair;
  pfxUpdateJointPairs(pair, 0, joint, states[0], states[1]);
  EXPECT_TRUE(pfxGetActive(pair));  // one body awake
  states[0].sleep();
  pfxUpdateJointPairs(pair, 0, joint, states[0], states[1]);
  EXPECT_FALSE(pfxGetActive(pair));
  states[0].wakeup();
  states[0].setMotionType(kPfxMotionTypeFixed);
  pfxUpdateJointPairs(pair, 0, joint, states[0], states[1]);
  EXPECT_FALSE(pfxGetActive(pair));
}
