// The seed's stable pipeline (chapter 4) built stage by stage through pfx/pfx.h, from the
// parameters the seed documents and nothing else: every other field keeps its default. A
// tower of ten boxes must stand on it, warm starting must carry the impulses from one frame
// to the next, and a stage given a parameter set with a required field missing must say
// which field and change nothing.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <string>
#include <thread>
#include <type_traits>
#include <vector>

#include "pfx/pfx.h"

namespace {

using namespace pfx;

constexpr PfxUInt32 kNumBoxes = 10;
constexpr PfxUInt32 kNumRigidBodies = kNumBoxes + 1;  // the ground is body 0
constexpr PfxUInt32 kMaxPairs = 64;
constexpr PfxUInt32 kMaxContacts = kMaxPairs;
constexpr PfxFloat kTimeStep = 0.016f;  // the seed's
constexpr PfxFloat kHalf = 0.5f;        // the boxes are 1 m cubes
// A standing tower settles by the contact slop and the narrow phase's rounding, not more.
constexpr PfxFloat kStandingDrift = 0.005f;

// 16-byte aligned scratch of at least `bytes`.
std::vector<PfxSortData16> alignedBuffer(PfxUInt32 bytes) {
  return std::vector<PfxSortData16>((bytes + sizeof(PfxSortData16) - 1) / sizeof(PfxSortData16));
}

template <typename T>
std::vector<unsigned char> bytesOf(const T* data, std::size_t count) {
  const auto* begin = reinterpret_cast<const unsigned char*>(data);
  return std::vector<unsigned char>(begin, begin + sizeof(T) * count);
}

// What a test switches off to see what it does; everything else is the seed's program.
struct SeedOptions {
  bool warmStart = true;      // false: PfxSetupContactConstraintsParam::warmStartFactor = 0
  bool matchContacts = true;  // false: PfxDetectCollisionParam::matchDistanceSq = 0
};

class SeedPipeline {
 public:
  explicit SeedPipeline(SeedOptions options = {}) : m_options(options) {
    addBox(0, PfxVector3(0, -1, 0), PfxVector3(10, 1, 10), kPfxMotionTypeFixed);
    for (PfxUInt32 i = 0; i < kNumBoxes; ++i) {
      addBox(i + 1, restPosition(i + 1), PfxVector3(kHalf, kHalf, kHalf), kPfxMotionTypeActive);
    }
    for (PfxUInt32 id = kMaxContacts; id > 0; --id) m_freeContactIds.push_back(id - 1);
    m_findPairsWork = alignedBuffer(pfxGetWorkBytesOfFindPairs(kMaxPairs));
    m_foundPairs = alignedBuffer(pfxGetPairBytesOfFindPairs(kMaxPairs));
    m_decomposeWork = alignedBuffer(pfxGetWorkBytesOfDecomposePairs(kMaxPairs, kMaxPairs));
    m_decomposedPairs = alignedBuffer(pfxGetPairBytesOfDecomposePairs(kMaxPairs, kMaxPairs));
    m_sortWork = alignedBuffer(sizeof(PfxBroadphaseProxy) * kNumRigidBodies);
    m_solverWork = alignedBuffer(pfxGetWorkBytesOfSolveConstraints(kNumRigidBodies, kMaxPairs));
  }

  static PfxVector3 restPosition(PfxUInt32 id) {
    return PfxVector3(0, kHalf + PfxFloat(id - 1) * 2 * kHalf, 0);
  }

  // Stages (1) to (3) and the set-up of (4): everything before pfxSolveConstraints.
  void collideAndSetUp() {
    applyExternalForce();
    broadphase();
    collision();
    setupConstraints();
  }
  // The rest of the frame: (4) solve, (5) integrate.
  void solveAndIntegrate() {
    PfxSolveConstraintsParam param;
    param.workBuff = m_solverWork.data();
    param.workBytes = static_cast<PfxUInt32>(m_solverWork.size() * sizeof(PfxSortData16));
    param.contactPairs = pairs();
    param.numContactPairs = m_numPairs;
    param.offsetContactManifolds = contacts;
    param.offsetRigidStates = states;
    param.offsetSolverBodies = solverBodies;
    param.numRigidBodies = kNumRigidBodies;
    param.iteration = 5;
    ASSERT_EQ(pfxSolveConstraints(param), PFX_OK) << pfxGetLastErrorDetail();

    PfxUpdateRigidStatesParam update;
    update.states = states;
    update.bodies = bodies;
    update.numRigidBodies = kNumRigidBodies;
    update.timeStep = kTimeStep;
    ASSERT_EQ(pfxUpdateRigidStates(update), PFX_OK) << pfxGetLastErrorDetail();
  }
  void step() {
    collideAndSetUp();
    solveAndIntegrate();
  }

  PfxConstraintPair* pairs() { return m_pairs[m_current]; }
  PfxUInt32 numPairs() const { return m_numPairs; }
  // Whether the pair of these bodies was there in the last frame as well.
  bool wasKept(PfxUInt32 idA, PfxUInt32 idB) const {
    return std::find(m_keptKeys.begin(), m_keptKeys.end(), pfxCreatePairKey(idA, idB)) !=
           m_keptKeys.end();
  }
  // Largest distance of a box from where it was built.
  PfxFloat largestDrift() const {
    PfxFloat drift = 0;
    for (PfxUInt32 id = 1; id < kNumRigidBodies; ++id) {
      drift = std::max(drift, (states[id].getPosition() - restPosition(id)).norm());
    }
    return drift;
  }

  PfxRigidState states[kNumRigidBodies];
  PfxRigidBody bodies[kNumRigidBodies];
  PfxCollidable collidables[kNumRigidBodies];
  PfxSolverBody solverBodies[kNumRigidBodies];
  PfxBroadphaseProxy proxies[kNumRigidBodies];
  PfxContactManifold contacts[kMaxContacts];

 private:
  // Seed chapter 3, "Create a Rigid Body".
  void addBox(PfxUInt32 id, const PfxVector3& position, const PfxVector3& half,
              PfxMotionType motionType) {
    PfxBox box(half);
    PfxShape shape;
    shape.reset();
    shape.setBox(box);
    collidables[id].reset();
    collidables[id].addShape(shape);
    collidables[id].finish();
    bodies[id].reset();
    bodies[id].setMass(1);
    bodies[id].setInertia(pfxCalcInertiaBox(half, 1));
    states[id].reset();
    states[id].setPosition(position);
    states[id].setMotionType(motionType);
    states[id].setRigidBodyId(id);
  }

  void applyExternalForce() {
    PfxApplyExternalForceParam param;
    param.states = states;
    param.bodies = bodies;
    param.numRigidBodies = kNumRigidBodies;
    param.timeStep = kTimeStep;
    ASSERT_EQ(pfxApplyExternalForce(param), PFX_OK) << pfxGetLastErrorDetail();
  }

  // Seed chapter 4, "Broad Phase": proxies along the axis of widest spread, sorted; the
  // pairs found; then decomposed against the last frame's into new, kept and removed.
  void broadphase() {
    const int axis = pfxChooseSweepAxis(states, kNumRigidBodies);
    const PfxVector3 worldCenter(0, 0, 0), worldExtent(100, 100, 100);
    for (PfxUInt32 id = 0; id < kNumRigidBodies; ++id) {
      ASSERT_EQ(pfxUpdateBroadphaseProxy(proxies[id], states[id], collidables[id], worldCenter,
                                         worldExtent, axis),
                PFX_OK);
    }
    ASSERT_EQ(pfxParallelSort(proxies, kNumRigidBodies, m_sortWork.data(),
                              static_cast<PfxUInt32>(m_sortWork.size() * sizeof(PfxSortData16))),
              PFX_OK);

    PfxFindPairsParam findPairsParam;
    findPairsParam.workBuff = m_findPairsWork.data();
    findPairsParam.workBytes = pfxGetWorkBytesOfFindPairs(kMaxPairs);
    findPairsParam.pairBuff = m_foundPairs.data();
    findPairsParam.pairBytes = pfxGetPairBytesOfFindPairs(kMaxPairs);
    findPairsParam.proxies = proxies;
    findPairsParam.numProxies = kNumRigidBodies;
    findPairsParam.maxPairs = kMaxPairs;
    findPairsParam.axis = axis;
    PfxFindPairsResult findPairsResult;
    ASSERT_EQ(pfxFindPairs(findPairsParam, findPairsResult), PFX_OK) << pfxGetLastErrorDetail();

    PfxDecomposePairsParam decomposePairsParam;
    decomposePairsParam.workBuff = m_decomposeWork.data();
    decomposePairsParam.workBytes = pfxGetWorkBytesOfDecomposePairs(kMaxPairs, kMaxPairs);
    decomposePairsParam.pairBuff = m_decomposedPairs.data();
    decomposePairsParam.pairBytes = pfxGetPairBytesOfDecomposePairs(kMaxPairs, kMaxPairs);
    decomposePairsParam.previousPairs = pairs();
    decomposePairsParam.numPreviousPairs = m_numPairs;
    decomposePairsParam.currentPairs = findPairsResult.pairs;
    decomposePairsParam.numCurrentPairs = findPairsResult.numPairs;
    PfxDecomposePairsResult result;
    ASSERT_EQ(pfxDecomposePairs(decomposePairsParam, result), PFX_OK) << pfxGetLastErrorDetail();

    for (PfxUInt32 i = 0; i < result.numOutRemovePairs; ++i) {
      m_freeContactIds.push_back(pfxGetContactId(result.outRemovePairs[i]));
    }
    for (PfxUInt32 i = 0; i < result.numOutNewPairs; ++i) {
      PfxBroadphasePair& pair = result.outNewPairs[i];
      ASSERT_FALSE(m_freeContactIds.empty());
      const PfxUInt32 contactId = m_freeContactIds.back();
      m_freeContactIds.pop_back();
      contacts[contactId].reset(pfxGetObjectIdA(pair), pfxGetObjectIdB(pair));
      pfxSetContactId(pair, contactId);
    }
    m_keptKeys.clear();
    for (PfxUInt32 i = 0; i < result.numOutKeepPairs; ++i) {
      m_keptKeys.push_back(result.outKeepPairs[i].key);
    }
    // The kept and the new pairs, by key, into the other of the two pair arrays.
    m_current = 1 - m_current;
    const auto byKey = [](const PfxBroadphasePair& a, const PfxBroadphasePair& b) {
      return a.key < b.key;
    };
    std::merge(result.outKeepPairs, result.outKeepPairs + result.numOutKeepPairs,
               result.outNewPairs, result.outNewPairs + result.numOutNewPairs, pairs(), byKey);
    m_numPairs = result.numOutKeepPairs + result.numOutNewPairs;
  }

  // Seed chapter 4, "Collision Detection": the kept points are refreshed, then the narrow
  // phase adds this frame's.
  void collision() {
    PfxRefreshContactsParam refresh;
    refresh.contactPairs = pairs();
    refresh.numContactPairs = m_numPairs;
    refresh.offsetContactManifolds = contacts;
    refresh.offsetRigidStates = states;
    refresh.numRigidBodies = kNumRigidBodies;
    ASSERT_EQ(pfxRefreshContacts(refresh), PFX_OK) << pfxGetLastErrorDetail();

    PfxDetectCollisionParam param;
    param.contactPairs = pairs();
    param.numContactPairs = m_numPairs;
    param.offsetContactManifolds = contacts;
    param.offsetRigidStates = states;
    param.offsetCollidables = collidables;
    param.numRigidBodies = kNumRigidBodies;
    if (!m_options.matchContacts) param.matchDistanceSq = 0;
    ASSERT_EQ(pfxDetectCollision(param), PFX_OK) << pfxGetLastErrorDetail();
  }

  // Seed chapter 4, "Constraint Calculation" (1) and (2).
  void setupConstraints() {
    PfxSetupSolverBodiesParam bodiesParam;
    bodiesParam.states = states;
    bodiesParam.bodies = bodies;
    bodiesParam.solverBodies = solverBodies;
    bodiesParam.numRigidBodies = kNumRigidBodies;
    ASSERT_EQ(pfxSetupSolverBodies(bodiesParam), PFX_OK) << pfxGetLastErrorDetail();

    PfxSetupContactConstraintsParam param;
    param.contactPairs = pairs();
    param.numContactPairs = m_numPairs;
    param.offsetContactManifolds = contacts;
    param.offsetRigidStates = states;
    param.offsetRigidBodies = bodies;
    param.offsetSolverBodies = solverBodies;
    param.numRigidBodies = kNumRigidBodies;
    param.timeStep = kTimeStep;
    param.separateBias = 0.2f;
    if (!m_options.warmStart) param.warmStartFactor = 0;
    ASSERT_EQ(pfxSetupContactConstraints(param), PFX_OK) << pfxGetLastErrorDetail();
  }

  SeedOptions m_options;
  // The pairs of this frame and of the last, used in turn (seed chapter 4, "Note").
  PfxBroadphasePair m_pairs[2][kMaxPairs];
  int m_current = 0;
  PfxUInt32 m_numPairs = 0;
  std::vector<PfxUInt64> m_keptKeys;
  std::vector<PfxUInt32> m_freeContactIds;
  std::vector<PfxSortData16> m_findPairsWork, m_foundPairs, m_decomposeWork, m_decomposedPairs,
      m_sortWork, m_solverWork;
};

constexpr int kTenSeconds = 625;  // frames of 0.016 s

PfxFloat driftAfterTenSeconds(SeedOptions options) {
  SeedPipeline seed(options);
  for (int frame = 0; frame < kTenSeconds && !::testing::Test::HasFatalFailure(); ++frame) {
    seed.step();
  }
  return seed.largestDrift();
}

TEST(SeedPipeline, TowerOfTenBoxesStandsOnTheDocumentedParametersAlone) {
  const PfxFloat drift = driftAfterTenSeconds({});
  ASSERT_FALSE(HasFatalFailure());
  EXPECT_LT(drift, kStandingDrift) << "a box moved " << drift << " m from where it was stacked";
}

TEST(SeedPipeline, WarmStartingCarriesTheImpulsesOverAndKeepsTheTowerUp) {
  SeedPipeline seed;
  for (int frame = 0; frame < 60; ++frame) seed.step();
  seed.collideAndSetUp();
  ASSERT_FALSE(HasFatalFailure());

  // At the start of this frame's solve, the points kept from the last frame hold the
  // impulses the last solve left, scaled by the warm start factor (1): together the points
  // under the tower carry its weight over the step, about what the solve will need again.
  PfxFloat groundImpulse = 0;
  PfxUInt32 keptPairsTouching = 0;
  for (PfxUInt32 i = 0; i < seed.numPairs(); ++i) {
    const PfxConstraintPair& pair = seed.pairs()[i];
    const PfxUInt32 idA = pfxGetObjectIdA(pair), idB = pfxGetObjectIdB(pair);
    const PfxContactManifold& manifold = seed.contacts[pfxGetContactId(pair)];
    if (!seed.wasKept(idA, idB) || manifold.getNumContacts() == 0) continue;
    ++keptPairsTouching;
    PfxFloat pairImpulse = 0;
    for (PfxUInt32 c = 0; c < manifold.getNumContacts(); ++c) {
      pairImpulse += manifold.getContactPoint(c).m_constraintRow[0].m_accumImpulse;
    }
    EXPECT_GT(pairImpulse, 0) << "pair " << idA << "-" << idB << " starts its solve from zero";
    if (idA == 0 || idB == 0) groundImpulse += pairImpulse;
  }
  EXPECT_EQ(keptPairsTouching, kNumBoxes);  // ground-box and box-box, all resting
  const PfxFloat towerWeightOverStep = kNumBoxes * 9.80665f * kTimeStep;
  EXPECT_NEAR(groundImpulse, towerWeightOverStep, 0.02f * towerWeightOverStep);

  // Without what is carried over, five iterations a frame hold the tower far worse:
  // neither with the impulses zeroed before the solve nor with the points' impulses not
  // handed on to this frame's points (matchDistanceSq 0, the default that once hid this).
  // (Before the direct solve of the stack's faces held their friction too, the tower fell;
  // now it sways by millimetres where, warm started, it stands to micrometres.)
  const PfxFloat warmDrift = driftAfterTenSeconds({});
  const PfxFloat coldDrift = driftAfterTenSeconds({/*warmStart=*/false, /*matchContacts=*/true});
  const PfxFloat unmatchedDrift =
      driftAfterTenSeconds({/*warmStart=*/true, /*matchContacts=*/false});
  ASSERT_FALSE(HasFatalFailure());
  std::printf("ten-box tower after 10 s: drift %.2e m warm started, %.2e m cold, %.2e m with "
              "points unmatched\n", warmDrift, coldDrift, unmatchedDrift);
  EXPECT_GT(coldDrift, 20 * warmDrift) << "the tower without warm starting";
  EXPECT_GT(unmatchedDrift, 20 * warmDrift) << "the tower without matched points";
}

// A rejected call: the code, a detail that names the parameter set and the field, and not
// a byte changed in what the pipeline holds.
class RejectedCall {
 public:
  explicit RejectedCall(SeedPipeline& seed)
      : m_seed(seed),
        m_states(bytesOf(seed.states, kNumRigidBodies)),
        m_solverBodies(bytesOf(seed.solverBodies, kNumRigidBodies)),
        m_contacts(bytesOf(seed.contacts, kMaxContacts)),
        m_pairs(bytesOf(seed.pairs(), seed.numPairs())),
        m_proxies(bytesOf(seed.proxies, kNumRigidBodies)) {}

  void expect(PfxInt32 result, PfxInt32 code, const std::string& field) const {
    EXPECT_EQ(result, code) << field;
    const std::string detail = pfxGetLastErrorDetail();
    EXPECT_NE(detail.find(field), std::string::npos) << "detail: " << detail;
    EXPECT_EQ(bytesOf(m_seed.states, kNumRigidBodies), m_states) << field;
    EXPECT_EQ(bytesOf(m_seed.solverBodies, kNumRigidBodies), m_solverBodies) << field;
    EXPECT_EQ(bytesOf(m_seed.contacts, kMaxContacts), m_contacts) << field;
    EXPECT_EQ(bytesOf(m_seed.pairs(), m_seed.numPairs()), m_pairs) << field;
    EXPECT_EQ(bytesOf(m_seed.proxies, kNumRigidBodies), m_proxies) << field;
  }

 private:
  SeedPipeline& m_seed;
  std::vector<unsigned char> m_states, m_solverBodies, m_contacts, m_pairs, m_proxies;
};

TEST(SeedPipeline, AMissingRequiredFieldIsNamedAndChangesNothing) {
  SeedPipeline seed;
  for (int frame = 0; frame < 10; ++frame) seed.step();
  seed.collideAndSetUp();
  ASSERT_FALSE(HasFatalFailure());
  ASSERT_GT(seed.numPairs(), 0u);
  const RejectedCall rejected(seed);

  PfxApplyExternalForceParam force;
  force.states = seed.states;
  force.bodies = seed.bodies;
  force.numRigidBodies = kNumRigidBodies;
  rejected.expect(pfxApplyExternalForce(force), PFX_ERR_INVALID_VALUE,
                  "PfxApplyExternalForceParam::timeStep");

  PfxFindPairsParam find;
  find.proxies = seed.proxies;
  find.numProxies = kNumRigidBodies;
  find.maxPairs = kMaxPairs;
  PfxFindPairsResult found;
  rejected.expect(pfxFindPairs(find, found), PFX_ERR_OUT_OF_BUFFER, "PfxFindPairsParam::pairBuff");

  PfxDetectCollisionParam detect;
  detect.contactPairs = seed.pairs();
  detect.numContactPairs = seed.numPairs();
  detect.offsetContactManifolds = seed.contacts;
  detect.offsetRigidStates = seed.states;
  detect.numRigidBodies = kNumRigidBodies;
  rejected.expect(pfxDetectCollision(detect), PFX_ERR_NULL_POINTER,
                  "PfxDetectCollisionParam::offsetCollidables");

  // A count, once given, is checked: one manifold too few names the count.
  PfxRefreshContactsParam refresh;
  refresh.contactPairs = seed.pairs();
  refresh.numContactPairs = seed.numPairs();
  refresh.offsetContactManifolds = seed.contacts;
  refresh.offsetRigidStates = seed.states;
  refresh.numRigidBodies = kNumRigidBodies;
  PfxUInt32 highestContactId = 0;
  for (PfxUInt32 i = 0; i < seed.numPairs(); ++i) {
    highestContactId = std::max(highestContactId, pfxGetContactId(seed.pairs()[i]));
  }
  refresh.numContactManifolds = highestContactId;
  rejected.expect(pfxRefreshContacts(refresh), PFX_ERR_OUT_OF_RANGE, "numContactManifolds");

  PfxSetupSolverBodiesParam solverBodies;
  solverBodies.states = seed.states;
  solverBodies.bodies = seed.bodies;
  solverBodies.numRigidBodies = kNumRigidBodies;
  rejected.expect(pfxSetupSolverBodies(solverBodies), PFX_ERR_NULL_POINTER,
                  "PfxSetupSolverBodiesParam::solverBodies");

  PfxSetupContactConstraintsParam setup;
  setup.contactPairs = seed.pairs();
  setup.numContactPairs = seed.numPairs();
  setup.offsetContactManifolds = seed.contacts;
  setup.offsetRigidStates = seed.states;
  setup.offsetRigidBodies = seed.bodies;
  setup.offsetSolverBodies = seed.solverBodies;
  setup.numRigidBodies = kNumRigidBodies;
  rejected.expect(pfxSetupContactConstraints(setup), PFX_ERR_INVALID_VALUE,
                  "PfxSetupContactConstraintsParam::timeStep");

  PfxSolveConstraintsParam solve;
  solve.contactPairs = seed.pairs();
  solve.numContactPairs = seed.numPairs();
  solve.offsetContactManifolds = seed.contacts;
  solve.offsetRigidStates = seed.states;
  solve.offsetSolverBodies = seed.solverBodies;
  solve.numRigidBodies = kNumRigidBodies;
  rejected.expect(pfxSolveConstraints(solve), PFX_ERR_OUT_OF_BUFFER,
                  "PfxSolveConstraintsParam::workBuff");

  PfxUpdateRigidStatesParam update;
  update.states = seed.states;
  update.bodies = seed.bodies;
  update.numRigidBodies = kNumRigidBodies;
  rejected.expect(pfxUpdateRigidStates(update), PFX_ERR_INVALID_VALUE,
                  "PfxUpdateRigidStatesParam::timeStep");
}

TEST(SeedPipeline, TheDetailIsThatOfTheCallingThread) {
  PfxUpdateRigidStatesParam update;  // no timeStep
  ASSERT_EQ(pfxUpdateRigidStates(update), PFX_ERR_INVALID_VALUE);
  const std::string mine = pfxGetLastErrorDetail();
  std::string theirs;
  std::thread other([&] {
    PfxSetupSolverBodiesParam bodies;
    bodies.numRigidBodies = 1;
    pfxSetupSolverBodies(bodies);
    theirs = pfxGetLastErrorDetail();
  });
  other.join();
  EXPECT_NE(theirs.find("PfxSetupSolverBodiesParam::states"), std::string::npos) << theirs;
  EXPECT_EQ(pfxGetLastErrorDetail(), mine);
}

// The seed's names reach pfx's things: a large mesh built with the seed's flags reports the
// seed's kind of mesh, a motion type and an error code pass under either name.
TEST(SeedNames, NameWhatPfxNames) {
  static_assert(std::is_same_v<ePfxMotionType, PfxMotionType>);
  static_assert(std::is_same_v<sce::PhysicsEffects::PfxRigidState, PfxRigidState>);
  EXPECT_EQ(mulPerElem(PfxVector3(1, 2, 3), PfxVector3(4, 5, 6)), PfxVector3(4, 10, 18));
  const PfxFloat vertices[] = {0, 0, 0, 1, 0, 0, 0, 0, 1, 1, 0, 1};
  const PfxUInt32 triangles[] = {0, 2, 1, 1, 2, 3};
  const std::pair<PfxUInt32, PfxUInt32> kinds[] = {
      {0, SCE_PFX_LARGE_MESH_TYPE_EXPANDED_ARRAY},
      {SCE_PFX_MESH_FLAG_USE_QUANTIZED, SCE_PFX_LARGE_MESH_TYPE_QUANTIZED_ARRAY},
      {SCE_PFX_MESH_FLAG_USE_BVH, SCE_PFX_LARGE_MESH_TYPE_EXPANDED_BVH},
      {SCE_PFX_MESH_FLAG_USE_BVH | SCE_PFX_MESH_FLAG_USE_QUANTIZED | SCE_PFX_MESH_FLAG_HIGH_QUALITY,
       SCE_PFX_LARGE_MESH_TYPE_QUANTIZED_BVH}};
  for (const auto& [flags, kind] : kinds) {
    PfxCreateLargeTriMeshParam param;
    param.m_vertices = vertices;
    param.m_numVertices = 4;
    param.m_triangles = triangles;
    param.m_numTriangles = 2;
    param.m_flags = flags;
    PfxLargeTriMesh mesh{};
    ASSERT_EQ(pfxCreateLargeTriMesh(mesh, param), SCE_PFX_OK);
    EXPECT_EQ(pfxGetLargeMeshType(mesh), kind) << "flags " << flags;
    pfxReleaseLargeTriMesh(mesh);
  }

  // A body far outside a small world: the seed's out-of-world error and behaviour.
  PfxRigidState state;
  state.reset();
  state.setPosition(PfxVector3(50, 0, 0));
  state.setMotionType(kPfxMotionTypeActive);
  PfxShape shape;
  shape.reset();
  shape.setSphere(PfxSphere(1));
  PfxCollidable collidable;
  collidable.reset();
  collidable.addShape(shape);
  collidable.finish();
  PfxBroadphaseProxy proxy;
  EXPECT_EQ(pfxUpdateBroadphaseProxy(proxy, state, collidable, PfxVector3::Zero(),
                                     PfxVector3::Constant(10), 0),
            SCE_PFX_ERR_OUT_OF_WORLD);
  std::vector<PfxSortData16> work = alignedBuffer(pfxGetWorkBytesOfUpdateBroadphaseProxies(1));
  PfxBroadphaseProxy proxies[1];
  PfxUpdateBroadphaseProxiesParam param;
  param.workBuff = work.data();
  param.workBytes = pfxGetWorkBytesOfUpdateBroadphaseProxies(1);
  param.offsetRigidStates = &state;
  param.offsetCollidables = &collidable;
  param.numRigidBodies = 1;
  param.proxiesX = proxies;
  param.worldExtent = PfxVector3::Constant(10);
  param.outOfWorldBehavior = SCE_PFX_OUT_OF_WORLD_BEHAVIOR_FIX_MOTION;
  PfxUpdateBroadphaseProxiesResult result;
  pfxUpdateBroadphaseProxies(param, result);
  EXPECT_EQ(result.numOutOfWorldProxies, 1u);
  EXPECT_EQ(state.getMotionType(), kPfxMotionTypeFixed);
}

}  // namespace
