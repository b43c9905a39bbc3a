// Sample 1_simple: the simple pipeline of seed chapter 4, driven stage by stage through the
// low-level API: forty spheres, boxes, capsules and cylinders dropped into a walled pen.
// Nothing is kept from one frame to the next: every pair the broad phase finds gets a fresh
// contact manifold, so there is no pair decomposition, no contact refresh and no warm start.
// That is cheaper and fine for bodies that scatter, not for stacks (sample 2_stable keeps
// what this one throws away).
//
// The functions below follow the chapter's sections in order: applyExternalForce,
// broadphase, collision, constraintSolver, integrate. Every parameter set is filled with the
// fields the chapter shows; the others keep pfx's defaults. Prints where the bodies are
// every two seconds and exits non-zero when one sank into the floor, left the pen or still
// flies after 10 s.
#include <algorithm>
#include <cstdio>
#include <vector>

#include "pfx/pfx.h"

using namespace pfx;

namespace {

// ---- The scene (seed chapter 3, "Create a Rigid Body").

constexpr int kNumDropped = 40;
constexpr int NUM_RIGIDBODIES = 5 + kNumDropped;  // floor, four walls, the dropped bodies
constexpr int MAX_PAIRS = 500;
constexpr PfxFloat kTimeStep = 0.016f;
constexpr PfxUInt32 kIterations = 5;
constexpr PfxFloat kPenHalfWidth = 5.0f;  // inner faces of the walls

PfxRigidState states[NUM_RIGIDBODIES];
PfxRigidBody bodies[NUM_RIGIDBODIES];
PfxCollidable collidables[NUM_RIGIDBODIES];
PfxSolverBody solverBodies[NUM_RIGIDBODIES];
PfxBroadphaseProxy proxies[NUM_RIGIDBODIES];
int numRigidBodies = 0;
int firstDropped = 0;

// One manifold per pair, rebuilt every frame: pair i uses contacts[i].
PfxContactManifold contacts[MAX_PAIRS];
PfxBroadphasePair* currentPairs = nullptr;
PfxUInt32 numCurrentPairs = 0;

// Work and pair buffers, 16-byte aligned and sized once for MAX_PAIRS (seed chapter 9,
// "Memory Management": nothing is allocated while the simulation runs).
std::vector<PfxSortData16> alignedBuffer(PfxUInt32 bytes) {
  return std::vector<PfxSortData16>((bytes + sizeof(PfxSortData16) - 1) / sizeof(PfxSortData16));
}
std::vector<PfxSortData16> sortWork, findPairsWork, findPairsBuff, solverWork;

const PfxVector3 worldCenter(0, 0, 0);
const PfxVector3 worldExtent(50, 50, 50);

// A body of one shape; a fixed one when inertia is not given.
void createBody(const PfxShape& shape, const PfxVector3& position, const PfxQuat& orientation,
                const PfxMatrix3* inertia) {
  const int id = numRigidBodies++;
  collidables[id].reset();
  collidables[id].addShape(shape);
  collidables[id].finish();
  bodies[id].reset();
  if (inertia) {
    bodies[id].setMass(1.0f);
    bodies[id].setInertia(*inertia);
  }
  states[id].reset();
  states[id].setPosition(position);
  states[id].setOrientation(orientation);
  states[id].setMotionType(inertia ? kPfxMotionTypeActive : kPfxMotionTypeFixed);
  states[id].setRigidBodyId(id);
}

PfxShape boxShape(const PfxVector3& half) {
  PfxShape shape;
  shape.reset();
  shape.setBox(PfxBox(half));
  return shape;
}

void createScene() {
  const PfxQuat upright = PfxQuat::Identity();
  createBody(boxShape(PfxVector3(10, 0.5f, 10)), PfxVector3(0, -0.5f, 0), upright, nullptr);
  for (int side = 0; side < 4; ++side) {
    const PfxFloat sign = side < 2 ? 1.0f : -1.0f;
    const PfxFloat centre = sign * (kPenHalfWidth + 0.25f);
    if (side % 2 == 0) {
      createBody(boxShape(PfxVector3(5.5f, 1, 0.25f)), PfxVector3(0, 1, centre), upright, nullptr);
    } else {
      createBody(boxShape(PfxVector3(0.25f, 1, 5.5f)), PfxVector3(centre, 1, 0), upright, nullptr);
    }
  }

  firstDropped = numRigidBodies;
  PfxShape shapes[4];
  PfxMatrix3 inertias[4];
  for (PfxShape& shape : shapes) shape.reset();
  shapes[0].setSphere(PfxSphere(0.3f));
  inertias[0] = pfxCalcInertiaSphere(0.3f, 1.0f);
  shapes[1].setBox(PfxBox(0.3f, 0.2f, 0.25f));
  inertias[1] = pfxCalcInertiaBox(PfxVector3(0.3f, 0.2f, 0.25f), 1.0f);
  shapes[2].setCapsule(PfxCapsule(0.3f, 0.2f));
  inertias[2] = pfxCalcInertiaCapsule(0.3f, 0.2f, 1.0f);
  shapes[3].setCylinder(PfxCylinder(0.25f, 0.25f));
  inertias[3] = pfxCalcInertiaCylinder(0.25f, 0.25f, 1.0f);
  for (int i = 0; i < kNumDropped; ++i) {
    const PfxVector3 position(-3.0f + 1.5f * (i % 5), 1.0f + 0.8f * (i / 5),
                              -1.5f + 0.75f * (i % 4));
    const PfxQuat tilted(Eigen::AngleAxis<PfxFloat>(0.3f * i, PfxVector3(1, 2, 3).normalized()));
    createBody(shapes[i % 4], position, tilted, &inertias[i % 4]);
  }

  sortWork = alignedBuffer(sizeof(PfxBroadphaseProxy) * NUM_RIGIDBODIES);
  findPairsWork = alignedBuffer(pfxGetWorkBytesOfFindPairs(MAX_PAIRS));
  findPairsBuff = alignedBuffer(pfxGetPairBytesOfFindPairs(MAX_PAIRS));
  solverWork = alignedBuffer(pfxGetWorkBytesOfSolveConstraints(NUM_RIGIDBODIES, MAX_PAIRS));
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
// overlap. The simple pipeline skips (4): each pair found takes the manifold of its index,
// reset, so that nothing of the last frame is carried over.

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

  currentPairs = findPairsResult.pairs;
  numCurrentPairs = findPairsResult.numPairs;
  for (PfxUInt32 i = 0; i < numCurrentPairs; ++i) {
    contacts[i].reset(pfxGetObjectIdA(currentPairs[i]), pfxGetObjectIdB(currentPairs[i]));
    pfxSetContactId(currentPairs[i], i);
  }
  return true;
}

// ---- "Collision Detection": the narrow phase writes each pair's contact points. (With
// fresh manifolds there is nothing to refresh.)

bool collision() {
  PfxDetectCollisionParam param;
  param.contactPairs = currentPairs;
  param.numContactPairs = numCurrentPairs;
  param.offsetContactManifolds = contacts;
  param.offsetRigidStates = states;
  param.offsetCollidables = collidables;
  param.numRigidBodies = numRigidBodies;
  return check(pfxDetectCollision(param), "pfxDetectCollision");
}

// ---- "Constraint Calculation": (1) the solver bodies, (2) the contacts' constraints, which
// start from zero impulses, (3) the solver.

bool constraintSolver() {
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
  PfxSolveConstraintsParam param;
  param.workBuff = solverWork.data();
  param.workBytes = static_cast<PfxUInt32>(solverWork.size() * sizeof(PfxSortData16));
  param.contactPairs = currentPairs;
  param.numContactPairs = numCurrentPairs;
  param.offsetContactManifolds = contacts;
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

bool physicsSimulate() {
  return applyExternalForce() && broadphase() && collision() && constraintSolver() && integrate();
}

// ---- What the sample prints and checks: the extremes of the dropped bodies' surfaces.

struct Extent {
  PfxFloat lowest = 1e9f, highest = -1e9f, outermost = 0, fastest = 0;
};

Extent measure() {
  Extent e;
  for (int id = firstDropped; id < numRigidBodies; ++id) {
    const PfxShape& shape = collidables[id].getShape(0);
    const PfxTransform3 pose = states[id].getTransform() * shape.getOffsetTransform();
    e.lowest = std::min(e.lowest, pfxGetSupportPoint(shape, pose, -PfxVector3::UnitY()).y());
    e.highest = std::max(e.highest, pfxGetSupportPoint(shape, pose, PfxVector3::UnitY()).y());
    for (int axis : {0, 2}) {
      const PfxVector3 out = PfxVector3::Unit(axis);
      e.outermost = std::max(e.outermost, pfxGetSupportPoint(shape, pose, out).dot(out));
      e.outermost = std::max(e.outermost, -pfxGetSupportPoint(shape, pose, -out).dot(out));
    }
    e.fastest = std::max(e.fastest, states[id].getLinearVelocity().norm());
  }
  return e;
}

}  // namespace

int main() {
  createScene();
  std::printf("1_simple: %d bodies dropped into a pen, steps of %.3f s, %u iterations\n",
              kNumDropped, kTimeStep, kIterations);
  std::printf("   time   pairs  points  lowest  highest  outermost  fastest\n");
  const int frames = 625;  // 10 s
  for (int frame = 1; frame <= frames; ++frame) {
    if (!physicsSimulate()) return 1;
    if (frame % 125 == 0) {
      PfxUInt32 points = 0;
      for (PfxUInt32 i = 0; i < numCurrentPairs; ++i) points += contacts[i].getNumContacts();
      const Extent e = measure();
      std::printf("%6.1f s  %6u  %6u  %6.3f  %7.3f  %9.3f  %7.3f\n", frame * kTimeStep,
                  numCurrentPairs, points, e.lowest, e.highest, e.outermost, e.fastest);
    }
  }
  // (Spheres and lying capsules may still roll: there is no rolling resistance.)
  const Extent e = measure();
  const bool ok = e.lowest > -0.02f && e.outermost < kPenHalfWidth + 0.02f && e.highest < 2.0f;
  std::printf(
      "%s (lowest point %.4f m, floor at 0; outermost %.3f m, walls at %.1f)\n",
      ok ? "all bodies lie in the pen, on its floor" : "A BODY SANK, ESCAPED OR STILL FLIES",
      e.lowest, e.outermost, kPenHalfWidth);
  return ok ? 0 : 1;
}
