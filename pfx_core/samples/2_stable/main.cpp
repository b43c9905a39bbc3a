// Sample 2_stable: the stable pipeline of seed chapter 4, driven stage by stage through the
// low-level API: a pyramid of 55 boxes and a tower of 10 on a fixed ground, and a chain of
// five boxes hanging by ball joints from a fixed beam, given a push. The pairs of the broad
// phase, their contact points and the solver's impulses are kept from frame to frame (the
// pairs in two arrays used in turn, the contact manifolds in an array with a free list of
// ids), which is what lets stacks stand on five iterations a frame.
//
// The functions below follow the chapter's sections in order: applyExternalForce,
// broadphase, collision, constraintSolver, integrate, and one stage the seed does not have:
// correctJointPositions, which pfx's solver leaves the joints' position errors to (without
// it this chain's joints open by about a centimetre a second). Every parameter set is
// filled with the fields the chapter shows; the others keep pfx's defaults. Prints where the
// structures are every two seconds and exits non-zero when one fell or a joint came apart.
#include <algorithm>
#include <cstdio>
#include <vector>

#include "pfx/pfx.h"

using namespace pfx;

namespace {

// ---- The scene (seed chapter 3, "Create a Rigid Body" and "Create a Joint").

constexpr int kPyramidBase = 10;
constexpr int kNumPyramidBoxes = kPyramidBase * (kPyramidBase + 1) / 2;
constexpr int kNumTowerBoxes = 10;
constexpr int kNumChainLinks = 5;
constexpr int NUM_RIGIDBODIES = 2 + kNumPyramidBoxes + kNumTowerBoxes + kNumChainLinks;
constexpr int NUM_JOINTS = kNumChainLinks;
constexpr int MAX_PAIRS = 1000;
constexpr int MAX_CONTACTS = MAX_PAIRS;
constexpr PfxFloat kTimeStep = 0.016f;
constexpr PfxUInt32 kIterations = 5;
constexpr PfxFloat kHalf = 0.5f;  // the boxes are 1 m cubes

PfxRigidState states[NUM_RIGIDBODIES];
PfxRigidBody bodies[NUM_RIGIDBODIES];
PfxCollidable collidables[NUM_RIGIDBODIES];
PfxSolverBody solverBodies[NUM_RIGIDBODIES];
PfxBroadphaseProxy proxies[NUM_RIGIDBODIES];
PfxJoint joints[NUM_JOINTS];
PfxConstraintPair jointPairs[NUM_JOINTS];
int numRigidBodies = 0;

// Contact manifolds, and the ids of those no pair holds.
PfxContactManifold contacts[MAX_CONTACTS];
std::vector<PfxUInt32> freeContactIds;

// This frame's pairs and the last frame's: the two arrays are used in turn.
PfxBroadphasePair pairsBuff[2][MAX_PAIRS];
int pairSwap = 0;
PfxUInt32 numPairs[2] = {0, 0};

// Work and pair buffers, 16-byte aligned and sized once for MAX_PAIRS (seed chapter 9,
// "Memory Management": nothing is allocated while the simulation runs).
std::vector<PfxSortData16> alignedBuffer(PfxUInt32 bytes) {
  return std::vector<PfxSortData16>((bytes + sizeof(PfxSortData16) - 1) / sizeof(PfxSortData16));
}
std::vector<PfxSortData16> sortWork, findPairsWork, findPairsBuff, decomposeWork, decomposeBuff,
    solverWork, jointCorrectionWork;

const PfxVector3 worldCenter(0, 0, 0);
const PfxVector3 worldExtent(100, 100, 100);

int createBox(const PfxVector3& position, const PfxVector3& half, PfxMotionType motionType) {
  const int id = numRigidBodies++;
  PfxBox box(half);
  PfxShape shape;
  shape.reset();
  shape.setBox(box);
  collidables[id].reset();
  collidables[id].addShape(shape);
  collidables[id].finish();
  bodies[id].reset();
  bodies[id].setMass(1.0f);
  bodies[id].setInertia(pfxCalcInertiaBox(half, 1.0f));
  states[id].reset();
  states[id].setPosition(position);
  states[id].setMotionType(motionType);
  states[id].setRigidBodyId(id);
  return id;
}

struct Structure {
  int firstId, numBoxes;
  std::vector<PfxVector3> built;  // where each box was placed
};

Structure pyramid, tower;
int beamId;

void createScene() {
  createBox(PfxVector3(0, -1, 0), PfxVector3(30, 1, 30), kPfxMotionTypeFixed);

  pyramid.firstId = numRigidBodies;
  for (int layer = 0; layer < kPyramidBase; ++layer) {
    const int count = kPyramidBase - layer;
    for (int i = 0; i < count; ++i) {
      const PfxVector3 position(-6.0f + (i - 0.5f * (count - 1)) * 1.02f, kHalf + layer, 0);
      createBox(position, PfxVector3(kHalf, kHalf, kHalf), kPfxMotionTypeActive);
      pyramid.built.push_back(position);
    }
  }
  pyramid.numBoxes = kNumPyramidBoxes;

  tower.firstId = numRigidBodies;
  for (int layer = 0; layer < kNumTowerBoxes; ++layer) {
    const PfxVector3 position(4.0f, kHalf + layer, 0);
    createBox(position, PfxVector3(kHalf, kHalf, kHalf), kPfxMotionTypeActive);
    tower.built.push_back(position);
  }
  tower.numBoxes = kNumTowerBoxes;

  // The chain: links 0.4 m long, 0.2 m apart, each joined to the one above by a ball joint
  // midway between them; the top one to the beam. The last link is pushed sideways.
  beamId = createBox(PfxVector3(12, 8, 0), PfxVector3(1, 0.1f, 0.1f), kPfxMotionTypeFixed);
  for (int i = 0; i < kNumChainLinks; ++i) {
    const int above = i == 0 ? beamId : beamId + i;
    const int id = createBox(PfxVector3(12, 7.5f - 0.6f * i, 0), PfxVector3(0.1f, 0.2f, 0.1f),
                             kPfxMotionTypeActive);
    PfxBallJointInitParam jointParam;
    jointParam.anchorPoint = PfxVector3(12, 7.8f - 0.6f * i, 0);
    pfxInitializeBallJoint(joints[i], states[above], states[id], jointParam);
  }
  states[beamId + kNumChainLinks].setLinearVelocity(PfxVector3(0, 0, 3));

  for (PfxUInt32 id = MAX_CONTACTS; id > 0; --id) freeContactIds.push_back(id - 1);
  sortWork = alignedBuffer(sizeof(PfxBroadphaseProxy) * NUM_RIGIDBODIES);
  findPairsWork = alignedBuffer(pfxGetWorkBytesOfFindPairs(MAX_PAIRS));
  findPairsBuff = alignedBuffer(pfxGetPairBytesOfFindPairs(MAX_PAIRS));
  decomposeWork = alignedBuffer(pfxGetWorkBytesOfDecomposePairs(MAX_PAIRS, MAX_PAIRS));
  decomposeBuff = alignedBuffer(pfxGetPairBytesOfDecomposePairs(MAX_PAIRS, MAX_PAIRS));
  solverWork =
      alignedBuffer(pfxGetWorkBytesOfSolveConstraints(NUM_RIGIDBODIES, MAX_PAIRS, NUM_JOINTS));
  jointCorrectionWork =
      alignedBuffer(pfxGetWorkBytesOfCorrectJointPositions(NUM_RIGIDBODIES, NUM_JOINTS));
}

// Every stage returns PFX_OK here; should one not, say which field of which parameter set
// it rejected, and stop.
bool check(PfxInt32 err, const char* stage) {
  if (err == PFX_OK) return true;
  std::printf("%s failed: %s (%s)\n", stage, pfxErrorString(err), pfxGetLastErrorDetail());
  return false;
}

// ---- Seed chapter 4, "Apply an External Force": gravity becomes velocity.

bool applyExternalForce() {
  PfxApplyExternalForceParam param;
  param.states = states;
  param.bodies = bodies;
  param.numRigidBodies = numRigidBodies;
  param.timeStep = kTimeStep;
  return check(pfxApplyExternalForce(param), "pfxApplyExternalForce");
}

// ---- "Broad Phase": (1) the axis, (2) the proxies, sorted, (3) the pairs whose boxes
// overlap, (4) composed with the last frame's pairs.

bool broadphase() {
  // (1) The axis along which the bodies spread the most.
  PfxVector3 s(0, 0, 0), s2(0, 0, 0);
  for (int id = 0; id < numRigidBodies; ++id) {
    const PfxVector3 c = states[id].getPosition();
    s += c;
    s2 += c.cwiseProduct(c);
  }
  const PfxVector3 v = s2 - s.cwiseProduct(s) / PfxFloat(numRigidBodies);
  int axis = 0;
  if (v[1] > v[0]) axis = 1;
  if (v[2] > v[axis]) axis = 2;

  // (2) One proxy per body along that axis, then sorted.
  for (int id = 0; id < numRigidBodies; ++id) {
    const PfxInt32 err = pfxUpdateBroadphaseProxy(proxies[id], states[id], collidables[id],
                                                  worldCenter, worldExtent, axis);
    if (err == PFX_ERR_OUT_OF_WORLD) {
      std::printf("body %d left the world\n", id);
      return false;
    }
    if (!check(err, "pfxUpdateBroadphaseProxy")) return false;
  }
  if (!check(pfxParallelSort(proxies, numRigidBodies, sortWork.data(),
                             static_cast<PfxUInt32>(sortWork.size() * sizeof(PfxSortData16))),
             "pfxParallelSort")) {
    return false;
  }

  // (3) The pairs whose boxes overlap.
  PfxFindPairsParam findPairsParam;
  findPairsParam.workBuff = findPairsWork.data();
  findPairsParam.workBytes = pfxGetWorkBytesOfFindPairs(MAX_PAIRS);
  findPairsParam.pairBuff = findPairsBuff.data();
  findPairsParam.pairBytes = pfxGetPairBytesOfFindPairs(MAX_PAIRS);
  findPairsParam.proxies = proxies;
  findPairsParam.numProxies = numRigidBodies;
  findPairsParam.maxPairs = MAX_PAIRS;
  findPairsParam.axis = axis;
  PfxFindPairsResult findPairsResult;
  if (!check(pfxFindPairs(findPairsParam, findPairsResult), "pfxFindPairs")) return false;

  // (4) Against the last frame's pairs: new, kept and removed.
  PfxBroadphasePair* previousPairs = pairsBuff[pairSwap];
  const PfxUInt32 numPreviousPairs = numPairs[pairSwap];
  PfxDecomposePairsParam decomposePairsParam;
  decomposePairsParam.workBuff = decomposeWork.data();
  decomposePairsParam.workBytes = pfxGetWorkBytesOfDecomposePairs(MAX_PAIRS, MAX_PAIRS);
  decomposePairsParam.pairBuff = decomposeBuff.data();
  decomposePairsParam.pairBytes = pfxGetPairBytesOfDecomposePairs(MAX_PAIRS, MAX_PAIRS);
  decomposePairsParam.previousPairs = previousPairs;
  decomposePairsParam.numPreviousPairs = numPreviousPairs;
  decomposePairsParam.currentPairs = findPairsResult.pairs;
  decomposePairsParam.numCurrentPairs = findPairsResult.numPairs;
  PfxDecomposePairsResult result;
  if (!check(pfxDecomposePairs(decomposePairsParam, result), "pfxDecomposePairs")) return false;

  // A new pair takes a manifold from the free list...
  for (PfxUInt32 i = 0; i < result.numOutNewPairs; ++i) {
    PfxBroadphasePair& pair = result.outNewPairs[i];
    const PfxUInt32 contactId = freeContactIds.back();
    freeContactIds.pop_back();
    contacts[contactId].reset(pfxGetObjectIdA(pair), pfxGetObjectIdB(pair));
    pfxSetContactId(pair, contactId);
  }
  // ...a removed one gives its manifold back; a kept one keeps its manifold, points and
  // impulses.
  for (PfxUInt32 i = 0; i < result.numOutRemovePairs; ++i) {
    freeContactIds.push_back(pfxGetContactId(result.outRemovePairs[i]));
  }

  // The new and the kept pairs, sorted, become this frame's in the other array.
  pairSwap = 1 - pairSwap;
  PfxBroadphasePair* currentPairs = pairsBuff[pairSwap];
  const auto byKey = [](const PfxBroadphasePair& a, const PfxBroadphasePair& b) {
    return a.key < b.key;
  };
  std::merge(result.outKeepPairs, result.outKeepPairs + result.numOutKeepPairs, result.outNewPairs,
             result.outNewPairs + result.numOutNewPairs, currentPairs, byKey);
  numPairs[pairSwap] = result.numOutKeepPairs + result.numOutNewPairs;
  return true;
}

// ---- "Collision Detection": the points kept from the last frame are refreshed (moved
// with their bodies, dropped when they no longer hold), then the narrow phase adds this
// frame's; a new point close to a kept one takes over its impulses.

bool collision() {
  PfxBroadphasePair* currentPairs = pairsBuff[pairSwap];
  const PfxUInt32 numCurrentPairs = numPairs[pairSwap];
  {
    PfxRefreshContactsParam param;
    param.contactPairs = currentPairs;
    param.numContactPairs = numCurrentPairs;
    param.offsetContactManifolds = contacts;
    param.offsetRigidStates = states;
    param.numRigidBodies = numRigidBodies;
    if (!check(pfxRefreshContacts(param), "pfxRefreshContacts")) return false;
  }
  PfxDetectCollisionParam param;
  param.contactPairs = currentPairs;
  param.numContactPairs = numCurrentPairs;
  param.offsetContactManifolds = contacts;
  param.offsetRigidStates = states;
  param.offsetCollidables = collidables;
  param.numRigidBodies = numRigidBodies;
  return check(pfxDetectCollision(param), "pfxDetectCollision");
}

// ---- "Constraint Calculation": (1) the solver bodies, (2) the contacts' and joints'
// constraints, warm started from the last frame's impulses, (3) the solver.

bool constraintSolver() {
  PfxBroadphasePair* currentPairs = pairsBuff[pairSwap];
  const PfxUInt32 numCurrentPairs = numPairs[pairSwap];
  {
    PfxSetupSolverBodiesParam param;
    param.states = states;
    param.bodies = bodies;
    param.solverBodies = solverBodies;
    param.numRigidBodies = numRigidBodies;
    if (!check(pfxSetupSolverBodies(param), "pfxSetupSolverBodies")) return false;
  }
  {
    PfxSetupContactConstraintsParam param;
    param.contactPairs = currentPairs;
    param.numContactPairs = numCurrentPairs;
    param.offsetContactManifolds = contacts;
    param.offsetRigidStates = states;
    param.offsetRigidBodies = bodies;
    param.offsetSolverBodies = solverBodies;
    param.numRigidBodies = numRigidBodies;
    param.timeStep = kTimeStep;
    param.separateBias = 0.2f;
    if (!check(pfxSetupContactConstraints(param), "pfxSetupContactConstraints")) return false;
  }
  {
    for (int i = 0; i < NUM_JOINTS; ++i) {
      pfxUpdateJointPairs(jointPairs[i], i, joints[i], states[joints[i].m_rigidBodyIdA],
                          states[joints[i].m_rigidBodyIdB]);
    }
    PfxSetupJointConstraintsParam param;
    param.jointPairs = jointPairs;
    param.numJointPairs = NUM_JOINTS;
    param.offsetJoints = joints;
    param.offsetRigidStates = states;
    param.offsetRigidBodies = bodies;
    param.offsetSolverBodies = solverBodies;
    param.numRigidBodies = numRigidBodies;
    param.timeStep = kTimeStep;
    if (!check(pfxSetupJointConstraints(param), "pfxSetupJointConstraints")) return false;
  }
  PfxSolveConstraintsParam param;
  param.workBuff = solverWork.data();
  param.workBytes = static_cast<PfxUInt32>(solverWork.size() * sizeof(PfxSortData16));
  param.contactPairs = currentPairs;
  param.numContactPairs = numCurrentPairs;
  param.offsetContactManifolds = contacts;
  param.jointPairs = jointPairs;
  param.numJointPairs = NUM_JOINTS;
  param.offsetJoints = joints;
  param.offsetRigidStates = states;
  param.offsetSolverBodies = solverBodies;
  param.numRigidBodies = numRigidBodies;
  param.iteration = kIterations;
  return check(pfxSolveConstraints(param), "pfxSolveConstraints");
}

// ---- "Position Calculation".

bool integrate() {
  PfxUpdateRigidStatesParam param;
  param.states = states;
  param.bodies = bodies;
  param.numRigidBodies = numRigidBodies;
  param.timeStep = kTimeStep;
  return check(pfxUpdateRigidStates(param), "pfxUpdateRigidStates");
}

// ---- pfx's own stage: the joints' position errors, removed by moving the bodies.

bool correctJointPositions() {
  PfxCorrectJointPositionsParam param;
  param.workBuff = jointCorrectionWork.data();
  param.workBytes = pfxGetWorkBytesOfCorrectJointPositions(NUM_RIGIDBODIES, NUM_JOINTS);
  param.jointPairs = jointPairs;
  param.numJointPairs = NUM_JOINTS;
  param.offsetJoints = joints;
  param.numJoints = NUM_JOINTS;
  param.offsetRigidStates = states;
  param.offsetRigidBodies = bodies;
  param.offsetSolverBodies = solverBodies;
  param.numRigidBodies = numRigidBodies;
  param.timeStep = kTimeStep;
  return check(pfxCorrectJointPositions(param), "pfxCorrectJointPositions");
}

bool physicsSimulate() {
  return applyExternalForce() && broadphase() && collision() && constraintSolver() && integrate() &&
         correctJointPositions();
}

// ---- What the sample prints and checks.

PfxFloat largestDrift(const Structure& structure) {
  PfxFloat drift = 0;
  for (int i = 0; i < structure.numBoxes; ++i) {
    const PfxVector3 position = states[structure.firstId + i].getPosition();
    drift = std::max(drift, (position - structure.built[i]).norm());
  }
  return drift;
}

// Distance between the two bodies' anchors of the joint that is furthest apart.
PfxFloat largestJointGap() {
  PfxFloat gap = 0;
  for (const PfxJoint& joint : joints) {
    const PfxVector3 anchorA = states[joint.m_rigidBodyIdA].getTransform() * joint.m_anchorA;
    const PfxVector3 anchorB = states[joint.m_rigidBodyIdB].getTransform() * joint.m_anchorB;
    gap = std::max(gap, (anchorA - anchorB).norm());
  }
  return gap;
}

PfxUInt32 numContactPoints() {
  PfxUInt32 points = 0;
  for (PfxUInt32 i = 0; i < numPairs[pairSwap]; ++i) {
    points += contacts[pfxGetContactId(pairsBuff[pairSwap][i])].getNumContacts();
  }
  return points;
}

}  // namespace

int main() {
  createScene();
  std::printf("2_stable: %d bodies, %d joints, steps of %.3f s, %u iterations\n", numRigidBodies,
              NUM_JOINTS, kTimeStep, kIterations);
  std::printf("   time   pairs  points  pyramid drift  tower drift  largest joint gap\n");
  const int frames = 1250;  // 20 s
  PfxFloat worstGap = 0;
  for (int frame = 1; frame <= frames; ++frame) {
    if (!physicsSimulate()) return 1;
    worstGap = std::max(worstGap, largestJointGap());
    if (frame % 125 == 0) {
      std::printf("%6.1f s  %6u  %6u  %11.4f m  %9.4f m  %13.2e m\n", frame * kTimeStep,
                  numPairs[pairSwap], numContactPoints(), largestDrift(pyramid),
                  largestDrift(tower), largestJointGap());
    }
  }
  const PfxFloat pyramidDrift = largestDrift(pyramid);
  const PfxFloat towerDrift = largestDrift(tower);
  const bool stands = pyramidDrift < 0.05f && towerDrift < 0.05f;
  const bool holds = worstGap < 0.001f;
  std::printf("pyramid and tower %s (largest drift %.4f and %.4f m, 0.05 allowed)\n",
              stands ? "stand" : "FELL", pyramidDrift, towerDrift);
  std::printf("chain %s (largest joint gap %.2e m, 0.001 allowed)\n",
              holds ? "holds" : "CAME APART", worstGap);
  return stands && holds ? 0 : 1;
}
