// Sample 7_serialize (seed chapter 7): a scene is run for two seconds, written to a file,
// read back into a new world, and both worlds are run on side by side; the sample prints
// whether they agree, bit for bit, at every step. On the way it reads the same file once
// more through the seed's own interface, pfxSerializeRead with its five callbacks, into
// the application's arrays, to show what the file holds.
//
// usage: sample_7_serialize [FILE]   (default: pfx_sample_serialize.pfxw in the working
// folder; the file is left there, so that it can be read again or sent with a report)
#include <cstdio>
#include <cstring>
#include <vector>

#include "pfx/high_level/pfx_body_init.h"
#include "pfx/high_level/pfx_ragdoll.h"
#include "pfx/high_level/pfx_serialize.h"

using namespace pfx;

namespace {

constexpr int kStepsBeforeSaving = 120;
constexpr int kStepsAfterLoading = 180;

// A ground, a tower of ten boxes, a pile of spheres and boxes poured beside it and a
// ragdoll dropped onto the pile: contacts that warm start, sleep, and joints.
bool buildScene(PfxWorld& world) {
  if (world.initialize(PfxWorldParam()) != PFX_OK) return false;
  PfxBodyInit ground;
  ground.mass = 0;
  ground.position = PfxVector3(0, PfxFloat(-0.5), 0);
  bool ok = pfxAddBody(world, pfxMakeShape(PfxBox(20, PfxFloat(0.5), 20)), ground) == PFX_OK;
  for (int level = 0; level < 10; ++level) {
    PfxBodyInit box;
    box.position = PfxVector3(-3, PfxFloat(0.25 + 0.5 * level), 0);
    ok = ok &&
         pfxAddBody(world, pfxMakeShape(PfxBox(PfxFloat(0.25), PfxFloat(0.25), PfxFloat(0.25))),
                    box) == PFX_OK;
  }
  for (int i = 0; i < 60; ++i) {
    PfxBodyInit body;
    body.position = PfxVector3(PfxFloat(1 + 0.3 * (i % 4)), PfxFloat(0.5 + 0.6 * (i / 8)),
                               PfxFloat(-0.6 + 0.4 * ((i / 4) % 2)));
    const PfxShape shape =
        (i % 3 == 0) ? pfxMakeShape(PfxSphere(PfxFloat(0.15)))
                     : pfxMakeShape(PfxBox(PfxFloat(0.12), PfxFloat(0.12), PfxFloat(0.12)));
    ok = ok && pfxAddBody(world, shape, body) == PFX_OK;
  }
  PfxRagdoll ragdoll;
  return ok && pfxAddRagdoll(world, PfxVector3(PfxFloat(1.5), 6, 0), PfxQuat::Identity(),
                             &ragdoll) == PFX_OK;
}

bool sameBits(const PfxRigidState& a, const PfxRigidState& b) {
  return a.getPosition() == b.getPosition() &&
         a.getOrientation().coeffs() == b.getOrientation().coeffs() &&
         a.getLinearVelocity() == b.getLinearVelocity() &&
         a.getAngularVelocity() == b.getAngularVelocity();
}

// The application's side of pfxSerializeRead: arrays that start empty and grow when the
// reader asks (the buffer resizing callback), and a progress line (the update callback).
struct ApplicationArrays {
  PfxWorldParam worldParam;
  double simulatedTime = 0;
  std::vector<PfxRigidState> states;
  std::vector<PfxRigidBody> bodies;
  std::vector<PfxCollidable> collidables;
  std::vector<PfxVector3> forces, torques;
  std::vector<PfxShape> shapes;
  std::vector<PfxUInt16> shapeIds;
  std::vector<PfxJoint> joints;
  std::vector<PfxJointCoupling> couplings;
  std::vector<PfxBroadphasePair> pairs, sleepingPairs;
  std::vector<PfxContactManifold> manifolds;
  std::vector<PfxUInt32> freeManifolds;
  std::vector<PfxUInt64> excludedPairs;
  std::vector<PfxConvexMesh*> convexMeshes;
  std::vector<PfxLargeTriMesh*> largeMeshes;
  int progressReports = 0;

  void resize(const PfxSerializeCapacity& c) {
    states.resize(c.numRigidBodies);
    bodies.resize(c.numRigidBodies);
    collidables.resize(c.numRigidBodies);
    forces.resize(c.numRigidBodies);
    torques.resize(c.numRigidBodies);
    shapes.resize(c.numShapes);
    shapeIds.resize(c.numShapes);
    joints.resize(c.numJoints);
    couplings.resize(c.numJointCouplings);
    pairs.resize(c.numContactPairs);
    sleepingPairs.resize(c.numSleepingPairs);
    manifolds.resize(c.numContactManifolds);
    freeManifolds.resize(c.numFreeManifolds);
    excludedPairs.resize(c.numExcludedPairs);
    convexMeshes.resize(c.numConvexMeshes);
    largeMeshes.resize(c.numLargeMeshes);
  }

  void point(PfxSerializeCapacity& c, PfxSerializeBuffer& b) {
    c.numRigidBodies = PfxUInt32(states.size());
    c.numShapes = PfxUInt32(shapes.size());
    c.numJoints = PfxUInt32(joints.size());
    c.numJointCouplings = PfxUInt32(couplings.size());
    c.numContactPairs = PfxUInt32(pairs.size());
    c.numSleepingPairs = PfxUInt32(sleepingPairs.size());
    c.numContactManifolds = PfxUInt32(manifolds.size());
    c.numFreeManifolds = PfxUInt32(freeManifolds.size());
    c.numExcludedPairs = PfxUInt32(excludedPairs.size());
    c.numConvexMeshes = PfxUInt32(convexMeshes.size());
    c.numLargeMeshes = PfxUInt32(largeMeshes.size());
    b.worldParam = &worldParam;
    b.simulatedTime = &simulatedTime;
    b.rigidStates = states.data();
    b.rigidBodies = bodies.data();
    b.collidables = collidables.data();
    b.forces = forces.data();
    b.torques = torques.data();
    b.shapes = shapes.data();
    b.shapeIds = shapeIds.data();
    b.joints = joints.data();
    b.jointCouplings = couplings.data();
    b.contactPairs = pairs.data();
    b.sleepingPairs = sleepingPairs.data();
    b.contactManifolds = manifolds.data();
    b.freeManifolds = freeManifolds.data();
    b.excludedPairKeys = excludedPairs.data();
    b.convexMeshes = convexMeshes.data();
    b.largeMeshes = largeMeshes.data();
  }
};

bool onInit(PfxSerializeCapacity& capacity, PfxSerializeBuffer& buffer, void* user) {
  static_cast<ApplicationArrays*>(user)->point(capacity, buffer);
  return true;
}

bool onResize(PfxSerializeCapacity& capacity, PfxSerializeBuffer& buffer,
              const PfxSerializeCapacity& loaded, void* user) {
  auto* arrays = static_cast<ApplicationArrays*>(user);
  arrays->resize(loaded);
  arrays->point(capacity, buffer);
  return true;
}

void onUpdate(PfxUInt64, PfxUInt64, void* user) {
  ++static_cast<ApplicationArrays*>(user)->progressReports;
}

void onTerm(const PfxSerializeCapacity& counts, const PfxSerializeBuffer&, void*) {
  std::printf(
      "  the file holds %u bodies, %u joints, %u contact pairs (%u asleep) and %u "
      "manifolds\n",
      counts.numRigidBodies, counts.numJoints, counts.numContactPairs, counts.numSleepingPairs,
      counts.numContactManifolds);
}

void onError(PfxInt32 code, const char* const* tags, PfxUInt32 numTags, void*) {
  std::printf("  read failed: %s at", pfxErrorString(code));
  for (PfxUInt32 i = 0; i < numTags; ++i) std::printf(" %s", tags[i]);
  std::printf("\n");
}

}  // namespace

int main(int argc, char** argv) {
  const char* path = argc > 1 ? argv[1] : "pfx_sample_serialize.pfxw";
  PfxWorld original;
  if (!buildScene(original)) {
    std::printf("the scene could not be built\n");
    return 1;
  }
  for (int i = 0; i < kStepsBeforeSaving; ++i) original.step();
  std::string error;
  if (pfxSaveWorld(original, path, &error) != PFX_OK) {
    std::printf("writing %s failed: %s\n", path, error.c_str());
    return 1;
  }
  std::FILE* file = std::fopen(path, "rb");
  std::fseek(file, 0, SEEK_END);
  std::printf("after %d steps: %u bodies written to %s, %ld bytes\n", kStepsBeforeSaving,
              original.getNumRigidBodies(), path, std::ftell(file));

  // The seed's interface: the file into the application's own arrays.
  std::rewind(file);
  ApplicationArrays arrays;
  PfxSerializeCallbacks callbacks;
  callbacks.init = onInit;
  callbacks.resize = onResize;
  callbacks.update = onUpdate;
  callbacks.term = onTerm;
  callbacks.error = onError;
  callbacks.userData = &arrays;
  const PfxInt32 readCode = pfxSerializeRead(file, callbacks);
  std::fclose(file);
  for (PfxConvexMesh* mesh : arrays.convexMeshes) pfxDeleteConvexMesh(mesh);
  for (PfxLargeTriMesh* mesh : arrays.largeMeshes) pfxDeleteLargeTriMesh(mesh);
  if (readCode != PFX_OK) return 1;
  std::printf("  read through pfxSerializeRead, %d progress reports, t = %.4f s\n",
              arrays.progressReports, arrays.simulatedTime);

  // The whole world, to continue it.
  PfxWorld restored;
  PfxSerializedMeshes meshes;
  if (pfxLoadWorld(restored, path, meshes, &error) != PFX_OK) {
    std::printf("reading %s failed: %s\n", path, error.c_str());
    return 1;
  }
  int firstDifference = -1;
  for (int step = 0; step < kStepsAfterLoading && firstDifference < 0; ++step) {
    original.step();
    restored.step();
    for (PfxUInt32 i = 0; i < original.getNumRigidBodies(); ++i) {
      if (!sameBits(original.getRigidState(i), restored.getRigidState(i))) firstDifference = step;
    }
  }
  if (firstDifference >= 0) {
    std::printf("the worlds DIFFER from step %d after loading\n", firstDifference);
    return 1;
  }
  std::printf(
      "the saved world and the one read back agree bit for bit over %d more steps "
      "(%u of %u bodies asleep at the end)\n",
      kStepsAfterLoading, original.getStats().numSleepingBodies, original.getNumRigidBodies());
  return 0;
}
