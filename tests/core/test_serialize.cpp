// Serialization (seed chapter 7): a mixed world saved at t = 5 s and loaded into a fresh
// world continues bit for bit for 10 s on one and two threads; write, read and write give
// the same bytes; the seed's callbacks are called as documented; meshes go through the
// utility allocator; files of either precision load in the other; every step parameter
// round-trips, files of version 1 still load and a newer version is refused.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <map>

#include "pfx_serialize_test_world.h"

using namespace pfx;
using namespace pfx_test;

namespace {

constexpr int kSaveStep = 300;  // 5 s at 1/60 s
constexpr int kResumeSteps = 600;

PfxLargeTriMesh& deformMeshOf(const PfxWorld& world, const MixedWorld& m,
                              const PfxSerializedMeshes& meshes) {
  const PfxLargeTriMesh* named = world.getCollidable(m.deformBody).getShape(0).getLargeTriMesh();
  for (PfxLargeTriMesh* mesh : meshes.largeMeshes()) {
    if (mesh == named) return *mesh;
  }
  ADD_FAILURE() << "the loaded deforming mesh is not among the loaded meshes";
  return *meshes.largeMeshes().front();
}

class SerializeResume : public ::testing::TestWithParam<PfxUInt32> {};

TEST_P(SerializeResume, LoadedWorldContinuesBitForBit) {
  MixedWorld original;
  buildMixedWorld(original, GetParam());
  for (int step = 0; step < kSaveStep; ++step) {
    driveMixedWorld(original.world, original, original.deform.mesh, step);
    ASSERT_EQ(original.world.step(), PFX_OK);
  }
  // The scene holds what the test claims to carry over.
  const PfxWorldStats& stats = original.world.getStats();
  EXPECT_GT(stats.numSleepingBodies, 0u);
  EXPECT_GT(stats.numSleepingPairs, 0u);
  EXPECT_GT(stats.numAwakeBodies, 0u);
  EXPECT_GT(stats.numContactPoints, 20u);
  // The steps of float (or double) 1/60 s, added up in double.
  EXPECT_NEAR(original.world.getSimulatedTime(), kSaveStep * double(PfxFloat(1) / 60), 1e-9);
  // A force pending at the save must act after the load as well.
  ASSERT_EQ(
      original.world.applyForce(original.pushedBody, PfxVector3(30, 0, 0), PfxVector3::Zero()),
      PFX_OK);

  const Bytes saved = saveWorld(original.world);
  PfxWorld loaded;
  PfxSerializedMeshes meshes;
  std::string error;
  ASSERT_EQ(loadWorld(loaded, meshes, saved, &error), PFX_OK) << error;
  EXPECT_EQ(meshes.largeMeshes().size(), 2u);
  EXPECT_EQ(meshes.convexMeshes().size(), 1u);  // three hulls share one mesh
  EXPECT_EQ(loaded.getSimulatedTime(), original.world.getSimulatedTime());
  EXPECT_EQ(loaded.getParam().numThreads, GetParam());
  EXPECT_TRUE(sameStates(original.world, loaded));
  EXPECT_EQ(saveWorld(loaded), saved) << "write, read, write changed the bytes";

  PfxLargeTriMesh& loadedDeform = deformMeshOf(loaded, original, meshes);
  for (int step = kSaveStep; step < kSaveStep + kResumeSteps; ++step) {
    driveMixedWorld(original.world, original, original.deform.mesh, step);
    driveMixedWorld(loaded, original, loadedDeform, step);
    ASSERT_EQ(original.world.step(), PFX_OK);
    ASSERT_EQ(loaded.step(), PFX_OK);
    ASSERT_TRUE(sameStates(original.world, loaded)) << "the worlds part at step " << step;
  }
  EXPECT_EQ(loaded.getSimulatedTime(), original.world.getSimulatedTime());
  // Everything else the step carries (pairs, manifolds, impulses, sleep) agrees too.
  EXPECT_EQ(saveWorld(loaded), saveWorld(original.world));
  // The comparison covered motion to the end, not a world come to rest: the chain, the
  // pendulums and the paddle at least still move.
  EXPECT_GE(original.world.getStats().numAwakeBodies, 9u);
}

INSTANTIATE_TEST_SUITE_P(Threads, SerializeResume, ::testing::Values(1u, 2u));

TEST(Serialize, LoadCanChooseTheThreadCountAndResultsStayTheSame) {
  MixedWorld original;
  buildMixedWorld(original, 1);
  for (int step = 0; step < 120; ++step) {
    driveMixedWorld(original.world, original, original.deform.mesh, step);
    ASSERT_EQ(original.world.step(), PFX_OK);
  }
  const Bytes saved = saveWorld(original.world);
  PfxLoadWorldOptions options;
  options.keepSavedNumThreads = false;
  options.numThreads = 2;
  PfxWorld loaded;
  PfxSerializedMeshes meshes;
  ASSERT_EQ(loadWorld(loaded, meshes, saved, nullptr, options), PFX_OK);
  EXPECT_EQ(loaded.getParam().numThreads, 2u);
  PfxLargeTriMesh& loadedDeform = deformMeshOf(loaded, original, meshes);
  for (int step = 120; step < 240; ++step) {
    driveMixedWorld(original.world, original, original.deform.mesh, step);
    driveMixedWorld(loaded, original, loadedDeform, step);
    ASSERT_EQ(original.world.step(), PFX_OK);
    ASSERT_EQ(loaded.step(), PFX_OK);
  }
  EXPECT_TRUE(sameStates(original.world, loaded));

  options.numThreads = PFX_MAX_THREADS + 1;
  std::string error;
  EXPECT_EQ(loadWorld(loaded, meshes, saved, &error, options), PFX_ERR_OUT_OF_RANGE);
  EXPECT_NE(error.find("numThreads"), std::string::npos) << error;
}

// Pairs whose spheres do not touch, the neighbours on a floor, all name one manifold that
// stays empty, in the world and in the world loaded from its file (which gives each pair a
// manifold of its own, as the format wants), and a sphere's pair with the floor holds room
// for its one point.
TEST(Serialize, PairsWithoutPointsShareOneEmptyManifoldBeforeAndAfter) {
  PfxWorld original;
  ASSERT_EQ(original.initialize(PfxWorldParam()), PFX_OK);
  addBody(original, pfxMakeShape(PfxBox(3, 0.5f, 3)), PfxVector3(0, -0.5f, 0), 0);
  for (int i = 0; i < 16; ++i) {
    // 10 cm spheres 25 cm apart: their bounds overlap, their surfaces are 5 cm apart.
    addBody(original, pfxMakeShape(PfxSphere(0.1f)),
            PfxVector3(0.25f * (i % 4), 0.1f, 0.25f * (i / 4)), 1);
  }
  for (int step = 0; step < 5; ++step) ASSERT_EQ(original.step(), PFX_OK);
  const auto expectSharing = [](const PfxWorld& world, const char* which) {
    const PfxContactManifold* shared = nullptr;
    PfxUInt32 numSharing = 0, numTouching = 0;
    for (PfxUInt32 i = 0; i < world.getNumContactPairs(); ++i) {
      const PfxConstraintPair& pair = world.getContactPair(i);
      const PfxContactManifold& manifold = world.getContactManifold(pair);
      if (manifold.getNumContacts() > 0) {
        ++numTouching;
        EXPECT_EQ(manifold.getRigidBodyIdA(), pfxGetObjectIdA(pair)) << which;
        EXPECT_EQ(manifold.getCapacity(), 1u) << which << ": room for a sphere's one point";
        continue;
      }
      if (!shared) shared = &manifold;
      EXPECT_EQ(&manifold, shared) << which << ": pair " << i << " has an empty one of its own";
      ++numSharing;
    }
    EXPECT_EQ(numTouching, 16u) << which << ": each sphere on the floor";
    // Bounds quantized to 3 cm in the default world overlap for some of the neighbours.
    EXPECT_GT(numSharing, 1u) << which << ": neighbours, several on one manifold";
  };
  expectSharing(original, "saved");
  const Bytes saved = saveWorld(original);
  PfxWorld loaded;
  PfxSerializedMeshes meshes;
  ASSERT_EQ(loadWorld(loaded, meshes, saved), PFX_OK);
  expectSharing(loaded, "loaded");
  EXPECT_EQ(saveWorld(loaded), saved);
  for (int step = 0; step < 30; ++step) {
    ASSERT_EQ(original.step(), PFX_OK);
    ASSERT_EQ(loaded.step(), PFX_OK);
  }
  EXPECT_TRUE(sameStates(original, loaded));
  expectSharing(loaded, "stepped after loading");
}

TEST(Serialize, EmptyAndUnsteppedWorldsRoundTrip) {
  PfxWorld empty;
  const Bytes emptyBytes = saveWorld(empty);
  PfxWorld loaded;
  PfxSerializedMeshes meshes;
  ASSERT_EQ(loadWorld(loaded, meshes, emptyBytes), PFX_OK);
  EXPECT_EQ(loaded.getNumRigidBodies(), 0u);
  EXPECT_EQ(saveWorld(loaded), emptyBytes);

  MixedWorld unstepped;
  buildMixedWorld(unstepped, 1);
  const Bytes bytes = saveWorld(unstepped.world);
  ASSERT_EQ(loadWorld(loaded, meshes, bytes), PFX_OK);
  EXPECT_EQ(loaded.getSimulatedTime(), 0);
  EXPECT_EQ(saveWorld(loaded), bytes);
  EXPECT_EQ(loaded.step(), PFX_OK);
}

TEST(Serialize, SavesAndLoadsByPath) {
  MixedWorld original;
  buildMixedWorld(original, 1);
  ASSERT_EQ(original.world.step(), PFX_OK);
  const std::string path = ::testing::TempDir() + "pfx_serialize_path.pfx";
  std::string error;
  ASSERT_EQ(pfxSaveWorld(original.world, path.c_str(), &error), PFX_OK) << error;
  PfxWorld loaded;
  PfxSerializedMeshes meshes;
  ASSERT_EQ(pfxLoadWorld(loaded, path.c_str(), meshes, &error), PFX_OK) << error;
  EXPECT_TRUE(sameStates(original.world, loaded));
  std::remove(path.c_str());
  EXPECT_EQ(pfxLoadWorld(loaded, path.c_str(), meshes, &error), PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(error, "cannot be opened for reading: No such file or directory");
  EXPECT_NE(std::string(pfxGetLastErrorDetail()).find(path), std::string::npos)
      << pfxGetLastErrorDetail();
  EXPECT_EQ(pfxSaveWorld(original.world, static_cast<const char*>(nullptr), &error),
            PFX_ERR_NULL_POINTER);
}

// The application's side of the seed's callbacks: arrays that start empty and grow when the
// reader asks.
struct AppBuffers {
  PfxWorldParam param;
  double time = 0;
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
  std::vector<PfxUInt64> excluded;
  std::vector<PfxConvexMesh*> convexMeshes;
  std::vector<PfxLargeTriMesh*> largeMeshes;
  PfxSerializeCapacity loaded;
  bool allowResize = true;
  int resizeCalls = 0;
  int termCalls = 0;
  std::vector<PfxUInt64> progress;
  PfxInt32 errorCode = PFX_OK;
  std::vector<std::string> errorTags;

  ~AppBuffers() {
    for (PfxConvexMesh* mesh : convexMeshes) pfxDeleteConvexMesh(mesh);
    for (PfxLargeTriMesh* mesh : largeMeshes) pfxDeleteLargeTriMesh(mesh);
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
    c.numExcludedPairs = PfxUInt32(excluded.size());
    c.numConvexMeshes = PfxUInt32(convexMeshes.size());
    c.numLargeMeshes = PfxUInt32(largeMeshes.size());
    b.worldParam = &param;
    b.simulatedTime = &time;
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
    b.excludedPairKeys = excluded.data();
    b.convexMeshes = convexMeshes.data();
    b.largeMeshes = largeMeshes.data();
  }

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
    excluded.resize(c.numExcludedPairs);
    convexMeshes.resize(c.numConvexMeshes, nullptr);
    largeMeshes.resize(c.numLargeMeshes, nullptr);
  }

  PfxSerializeCallbacks callbacks() {
    PfxSerializeCallbacks cb;
    cb.userData = this;
    cb.init = [](PfxSerializeCapacity& c, PfxSerializeBuffer& b, void* self) {
      static_cast<AppBuffers*>(self)->point(c, b);
      return true;
    };
    cb.term = [](const PfxSerializeCapacity& c, const PfxSerializeBuffer&, void* self) {
      static_cast<AppBuffers*>(self)->loaded = c;
      ++static_cast<AppBuffers*>(self)->termCalls;
    };
    cb.resize = [](PfxSerializeCapacity& c, PfxSerializeBuffer& b, const PfxSerializeCapacity& need,
                   void* self) {
      AppBuffers& app = *static_cast<AppBuffers*>(self);
      ++app.resizeCalls;
      if (!app.allowResize) return false;
      app.resize(need);
      app.point(c, b);
      return true;
    };
    cb.update = [](PfxUInt64 done, PfxUInt64 total, void* self) {
      EXPECT_LE(done, total);
      static_cast<AppBuffers*>(self)->progress.push_back(done);
    };
    cb.error = [](PfxInt32 code, const char* const* tags, PfxUInt32 numTags, void* self) {
      AppBuffers& app = *static_cast<AppBuffers*>(self);
      app.errorCode = code;
      app.errorTags.assign(tags, tags + numTags);
    };
    return cb;
  }
};

TEST(Serialize, SeedCallbacksReadIntoTheApplicationsArraysAndWriteThemBack) {
  MixedWorld original;
  buildMixedWorld(original, 1);
  for (int step = 0; step < 120; ++step) {
    driveMixedWorld(original.world, original, original.deform.mesh, step);
    ASSERT_EQ(original.world.step(), PFX_OK);
  }
  const Bytes saved = saveWorld(original.world);

  AppBuffers app;
  FilePtr in = fileWith(saved);
  ASSERT_EQ(pfxSerializeRead(in.get(), app.callbacks()), PFX_OK) << pfxGetLastErrorDetail();
  EXPECT_EQ(app.resizeCalls, 1);
  EXPECT_EQ(app.termCalls, 1);
  EXPECT_EQ(app.loaded.numRigidBodies, original.world.getNumRigidBodies());
  EXPECT_EQ(app.loaded.numJoints, original.world.getNumJoints());
  EXPECT_EQ(app.loaded.numShapes, 2u);  // the compound's
  EXPECT_EQ(app.loaded.numLargeMeshes, 2u);
  EXPECT_EQ(app.loaded.numConvexMeshes, 1u);
  EXPECT_EQ(app.loaded.numContactPairs + app.loaded.numSleepingPairs,
            original.world.getNumContactPairs());
  ASSERT_EQ(app.progress.size(), 8u);  // once per section
  EXPECT_EQ(app.progress.back(), saved.size());
  EXPECT_TRUE(std::is_sorted(app.progress.begin(), app.progress.end()));
  EXPECT_EQ(std::memcmp(app.states.data(), original.world.getRigidStates(),
                        sizeof(PfxRigidState) * app.states.size()),
            0);
  EXPECT_EQ(ftell(in.get()), long(saved.size())) << "the reader stops at the file's end";

  // Written back from the application's arrays, the bytes are the same.
  FilePtr out(std::tmpfile());
  app.termCalls = 0;
  ASSERT_EQ(pfxSerializeWrite(out.get(), app.callbacks()), PFX_OK) << pfxGetLastErrorDetail();
  EXPECT_EQ(app.termCalls, 1);
  EXPECT_EQ(bytesOf(out.get()), saved);
}

// The writer runs the reader's checks on its bytes first: what it cannot read back, it does
// not write.
TEST(Serialize, WriteRejectsWhatTheReaderWouldAndWritesNothing) {
  SmallWorld small;
  const Bytes saved = saveWorld(small.world);
  AppBuffers app;
  FilePtr in = fileWith(saved);
  ASSERT_EQ(pfxSerializeRead(in.get(), app.callbacks()), PFX_OK) << pfxGetLastErrorDetail();
  ASSERT_FALSE(app.pairs.empty());

  // A pair both awake and asleep, each with a manifold of its own.
  std::vector<PfxBroadphasePair> sleeping = app.sleepingPairs;
  PfxBroadphasePair twin = app.pairs[0];
  app.manifolds.push_back(app.manifolds[pfxGetContactId(twin)]);
  pfxSetContactId(twin, PfxUInt32(app.manifolds.size() - 1));
  app.sleepingPairs.insert(
      std::upper_bound(
          app.sleepingPairs.begin(), app.sleepingPairs.end(), twin,
          [](const PfxBroadphasePair& a, const PfxBroadphasePair& b) { return a.key < b.key; }),
      twin);
  FilePtr out(std::tmpfile());
  EXPECT_EQ(pfxSerializeWrite(out.get(), app.callbacks()), PFX_ERR_OUT_OF_RANGE);
  EXPECT_EQ(app.errorTags, (std::vector<std::string>{"contacts", "sleeping pairs", "key"}));
  EXPECT_EQ(std::ftell(out.get()), 0);
  app.sleepingPairs = sleeping;
  app.manifolds.pop_back();

  // A state the world would reject.
  PfxRigidState state = app.states[1];
  state.setOrientation(PfxQuat(2, 0, 0, 0));
  app.states[1] = state;
  EXPECT_EQ(pfxSerializeWrite(out.get(), app.callbacks()), PFX_ERR_INVALID_VALUE);
  EXPECT_EQ(app.errorTags, (std::vector<std::string>{"bodies", "body 1", "state"}));
  EXPECT_EQ(std::ftell(out.get()), 0);
}

TEST(Serialize, ReadIntoBuffersTooSmallFailsAndLeavesThemAsTheyWere) {
  MixedWorld original;
  buildMixedWorld(original, 1);
  ASSERT_EQ(original.world.step(), PFX_OK);
  const Bytes saved = saveWorld(original.world);

  AppBuffers app;
  app.resize(PfxSerializeCapacity{});
  app.states.resize(3);
  app.bodies.resize(3);
  app.collidables.resize(3);
  app.forces.resize(3);
  app.torques.resize(3);
  std::memset(static_cast<void*>(app.states.data()), 0x5a, sizeof(PfxRigidState) * 3);
  const std::vector<PfxRigidState> before = app.states;
  app.allowResize = false;
  FilePtr in = fileWith(saved);
  EXPECT_EQ(pfxSerializeRead(in.get(), app.callbacks()), PFX_ERR_OUT_OF_BUFFER);
  EXPECT_EQ(app.resizeCalls, 1);
  EXPECT_EQ(app.termCalls, 0);
  EXPECT_EQ(app.errorCode, PFX_ERR_OUT_OF_BUFFER);
  EXPECT_EQ(app.errorTags, (std::vector<std::string>{"buffer", "numRigidBodies"}));
  EXPECT_EQ(std::memcmp(app.states.data(), before.data(), sizeof(PfxRigidState) * 3), 0);
  EXPECT_TRUE(app.convexMeshes.empty());
  EXPECT_NE(std::string(pfxGetLastErrorDetail()).find("pfxSerializeRead: buffer/numRigidBodies"),
            std::string::npos)
      << pfxGetLastErrorDetail();
}

TEST(Serialize, RejectsNullArgumentsAndArrays) {
  AppBuffers app;
  PfxSerializeCallbacks callbacks = app.callbacks();
  EXPECT_EQ(pfxSerializeRead(nullptr, callbacks), PFX_ERR_NULL_POINTER);
  EXPECT_EQ(app.errorCode, PFX_ERR_NULL_POINTER);
  EXPECT_TRUE(app.errorTags.empty());
  FilePtr file(std::tmpfile());
  callbacks.init = nullptr;
  EXPECT_EQ(pfxSerializeWrite(file.get(), callbacks), PFX_ERR_NULL_POINTER);
  // Bodies to write but no states to write them from.
  callbacks.init = [](PfxSerializeCapacity& c, PfxSerializeBuffer& b, void* self) {
    static_cast<AppBuffers*>(self)->point(c, b);
    c.numRigidBodies = 2;
    return true;
  };
  EXPECT_EQ(pfxSerializeWrite(file.get(), callbacks), PFX_ERR_NULL_POINTER);
  EXPECT_NE(std::string(pfxGetLastErrorDetail()).find("rigidStates"), std::string::npos);
  EXPECT_EQ(std::ftell(file.get()), 0) << "nothing is written when the call fails";
}

// Counts what the utility allocator hands out and takes back.
std::map<void*, std::size_t> g_allocated;
void* countingAllocate(std::size_t bytes, std::size_t alignment) {
  void* p = std::aligned_alloc(alignment, (bytes + alignment - 1) / alignment * alignment);
  g_allocated[p] = alignment;
  return p;
}
void countingFree(void* p) {
  EXPECT_EQ(g_allocated.erase(p), 1u) << "freed what the allocator did not allocate";
  std::free(p);
}

TEST(Serialize, MeshesGoThroughTheUtilityAllocator) {
  EXPECT_EQ(pfxSetUtilityAllocator(countingAllocate, nullptr), PFX_ERR_NULL_POINTER);
  ASSERT_EQ(pfxSetUtilityAllocator(countingAllocate, countingFree), PFX_OK);
  {
    MixedWorld original;
    buildMixedWorld(original, 1);
    // The terrain's and the deforming mesh's blocks.
    EXPECT_EQ(g_allocated.size(), 2u);
    ASSERT_EQ(original.world.step(), PFX_OK);
    const Bytes saved = saveWorld(original.world);
    EXPECT_EQ(g_allocated.size(), 2u) << "a save keeps nothing";
    {
      PfxWorld loaded;
      PfxSerializedMeshes meshes;
      ASSERT_EQ(loadWorld(loaded, meshes, saved), PFX_OK);
      // Two large meshes (struct and block each) and one convex mesh.
      EXPECT_EQ(g_allocated.size(), 2u + 5u);
      for (const auto& entry : g_allocated) EXPECT_GE(entry.second, PFX_BUFFER_ALIGNMENT);
    }
    EXPECT_EQ(g_allocated.size(), 2u);
    PfxLargeTriMesh* heap = pfxNewLargeTriMesh();
    ASSERT_NE(heap, nullptr);
    ASSERT_EQ(pfxCreateLargeTriMesh(*heap, original.deformSource.param(0)), PFX_OK);
    EXPECT_EQ(g_allocated.size(), 4u);
    pfxDeleteLargeTriMesh(heap);
    PfxConvexMesh* hull = pfxNewConvexMesh();
    EXPECT_EQ(g_allocated.size(), 3u);
    pfxDeleteConvexMesh(hull);
  }
  EXPECT_TRUE(g_allocated.empty());
  ASSERT_EQ(pfxSetUtilityAllocator(nullptr, nullptr), PFX_OK);
}

std::string fixturePath(const char* precision) {
  return std::string(PFX_TEST_DATA_DIR) + "/serialize_" + precision + ".pfx";
}

// A pile on shock propagation, with every other step parameter off its default as well:
// each one comes back, and the loaded pile goes on bit for bit.
TEST(Serialize, EveryStepParameterRoundTrips) {
  PfxWorldParam param;
  param.worldCenter = PfxVector3(1, 2, 3);
  param.worldExtent = PfxVector3(50, 60, 70);
  param.gravity = PfxVector3(0.5f, -9, 0);
  param.timeStep = PfxFloat(1) / 120;
  param.subStep = 2;
  param.iteration = 3;
  param.separateBias = PfxFloat(0.3);
  param.contactSlop = PfxFloat(0.004);
  param.contactMargin = PfxFloat(0.03);
  param.restitutionThreshold = PfxFloat(0.5);
  param.enableShockPropagation = true;
  param.measureConservation = true;
  param.measureStages = true;
  param.outOfWorldBehavior = PFX_OUT_OF_WORLD_BEHAVIOR_REMOVE_PROXY;
  param.enableSleep = false;
  param.sleepLinearVelocity = PfxFloat(0.1);
  param.sleepAngularVelocity = PfxFloat(0.2);
  param.sleepTime = PfxFloat(0.7);
  param.numThreads = 2;
  PfxWorld original;
  ASSERT_EQ(original.initialize(param), PFX_OK);
  addBody(original, pfxMakeShape(PfxBox(5, 0.5f, 5)), PfxVector3(0, -0.5f, 0), 0);
  for (int level = 0; level < 4; ++level) {
    addBody(original, pfxMakeShape(PfxBox(0.5f, 0.25f, 0.5f)),
            PfxVector3(0.05f * level, 0.25f + 0.5f * level, 0), 1);
  }
  for (int step = 0; step < 30; ++step) ASSERT_EQ(original.step(), PFX_OK);

  PfxWorld loaded;
  PfxSerializedMeshes meshes;
  std::string error;
  const Bytes saved = saveWorld(original);
  EXPECT_EQ(getU32(saved, 8), PFX_SERIALIZE_VERSION);
  ASSERT_EQ(loadWorld(loaded, meshes, saved, &error), PFX_OK) << error;
  const PfxWorldParam& back = loaded.getParam();
  EXPECT_EQ(back.worldCenter, param.worldCenter);
  EXPECT_EQ(back.worldExtent, param.worldExtent);
  EXPECT_EQ(back.gravity, param.gravity);
  EXPECT_EQ(back.timeStep, param.timeStep);
  EXPECT_EQ(back.subStep, param.subStep);
  EXPECT_EQ(back.iteration, param.iteration);
  EXPECT_EQ(back.pipeline, param.pipeline);
  EXPECT_EQ(back.separateBias, param.separateBias);
  EXPECT_EQ(back.contactSlop, param.contactSlop);
  EXPECT_EQ(back.contactMargin, param.contactMargin);
  EXPECT_EQ(back.restitutionThreshold, param.restitutionThreshold);
  EXPECT_TRUE(back.enableShockPropagation);
  EXPECT_TRUE(back.measureConservation);
  EXPECT_TRUE(back.measureStages);
  EXPECT_EQ(back.outOfWorldBehavior, param.outOfWorldBehavior);
  EXPECT_FALSE(back.enableSleep);
  EXPECT_EQ(back.sleepLinearVelocity, param.sleepLinearVelocity);
  EXPECT_EQ(back.sleepAngularVelocity, param.sleepAngularVelocity);
  EXPECT_EQ(back.sleepTime, param.sleepTime);
  EXPECT_EQ(back.numThreads, param.numThreads);
  for (int step = 0; step < 60; ++step) {
    ASSERT_EQ(original.step(), PFX_OK);
    ASSERT_EQ(loaded.step(), PFX_OK);
    ASSERT_TRUE(sameStates(original, loaded)) << "the piles part at step " << step;
  }
}

// A box tumbling in free flight carries what rounding left out of its orientation and
// spin from step to step (pfxIntegrate); version 2 saves the carries, so that the loaded
// box goes on to the same bits.
TEST(Serialize, TheIntegratorsCarriesRoundTrip) {
  PfxWorldParam param;
  param.gravity = PfxVector3::Zero();
  param.enableSleep = false;
  PfxWorld original;
  ASSERT_EQ(original.initialize(param), PFX_OK);
  PfxBodyInit tumbling;
  tumbling.angularVelocity = PfxVector3(0.02f, 10, 0);
  PfxUInt32 id = 0;
  ASSERT_EQ(pfxAddBody(original, pfxMakeShape(PfxBox(0.5f, 0.25f, 0.125f)), tumbling, &id),
            PFX_OK);
  for (int step = 0; step < 60; ++step) ASSERT_EQ(original.step(), PFX_OK);
  const PfxRigidState& saved = original.getRigidState(id);
  ASSERT_FALSE(saved.getOrientationCarry().coeffs().isZero(0));
  ASSERT_FALSE(saved.getAngularVelocityCarry().isZero(0));

  PfxWorld loaded;
  PfxSerializedMeshes meshes;
  std::string error;
  ASSERT_EQ(loadWorld(loaded, meshes, saveWorld(original), &error), PFX_OK) << error;
  EXPECT_TRUE(sameStates(original, loaded));
  for (int step = 0; step < 120; ++step) {
    ASSERT_EQ(original.step(), PFX_OK);
    ASSERT_EQ(loaded.step(), PFX_OK);
  }
  EXPECT_TRUE(sameStates(original, loaded));
}

// The files in tests/core/data were written in version 1, before the step parameters that
// version 2 added: they load, with the defaults for what they lack, and are saved again in
// the current version.
TEST(Serialize, Version1FilesLoadWithTheDefaultsForWhatTheyLack) {
  for (const char* precision : {"float", "double"}) {
    FilePtr file(std::fopen(fixturePath(precision).c_str(), "rb"));
    ASSERT_TRUE(file) << fixturePath(precision);
    const Bytes version1 = bytesOf(file.get());
    ASSERT_EQ(getU32(version1, 8), 1u);
    PfxWorldParam shockOn;
    shockOn.enableShockPropagation = true;
    PfxWorld loaded;
    ASSERT_EQ(loaded.initialize(shockOn), PFX_OK);
    PfxSerializedMeshes meshes;
    std::string error;
    ASSERT_EQ(loadWorld(loaded, meshes, version1, &error), PFX_OK) << precision << ": " << error;
    EXPECT_EQ(loaded.getParam().enableShockPropagation, PfxWorldParam().enableShockPropagation);
    EXPECT_GT(loaded.getNumRigidBodies(), 10u);
    const Bytes resaved = saveWorld(loaded);
    EXPECT_EQ(getU32(resaved, 8), PFX_SERIALIZE_VERSION);
    PfxWorld again;
    ASSERT_EQ(loadWorld(again, meshes, resaved, &error), PFX_OK) << error;
    EXPECT_TRUE(sameStates(loaded, again));
  }
}

// A version-2 file is a version-3 file without the last byte of its parameters
// (measureStages): it loads with that parameter's default and the rest as saved.
TEST(Serialize, Version2FilesLoadWithoutTheStageTimes) {
  PfxWorldParam param;
  param.enableShockPropagation = true;
  param.measureStages = true;
  PfxWorld original;
  ASSERT_EQ(original.initialize(param), PFX_OK);
  addBody(original, pfxMakeShape(PfxBox(5, 0.5f, 5)), PfxVector3(0, -0.5f, 0), 0);
  addBody(original, pfxMakeShape(PfxSphere(0.5f)), PfxVector3(0, 2, 0), 1);
  for (int step = 0; step < 10; ++step) ASSERT_EQ(original.step(), PFX_OK);
  const Bytes version3 = saveWorld(original);
  const std::size_t parameters = sectionPayload(version3, "PARM");
  const PfxUInt64 parameterBytes = getU64(version3, parameters - 8);
  ASSERT_EQ(version3[parameters + parameterBytes - 1], 1);  // measureStages, last
  Bytes version2(version3.begin(), version3.begin() + parameters + parameterBytes - 1);
  version2.insert(version2.end(), version3.begin() + parameters + parameterBytes, version3.end());
  putU32(version2, 8, 2);
  putU64(version2, 16, getU64(version3, 16) - 1);  // the body's length
  putU64(version2, parameters - 8, parameterBytes - 1);
  resealChecksum(version2);

  PfxWorld loaded;
  PfxSerializedMeshes meshes;
  std::string error;
  ASSERT_EQ(loadWorld(loaded, meshes, version2, &error), PFX_OK) << error;
  EXPECT_FALSE(loaded.getParam().measureStages);
  EXPECT_TRUE(loaded.getParam().enableShockPropagation);
  EXPECT_TRUE(sameStates(original, loaded));
  EXPECT_EQ(getU32(saveWorld(loaded), 8), PFX_SERIALIZE_VERSION);
}

// A file of a version this build does not know yet is refused, naming the version, and the
// world it was to be loaded into is left as it was.
TEST(Serialize, ANewerVersionIsRefusedAndChangesNothing) {
  SmallWorld target;
  const Bytes before = saveWorld(target.world);
  Bytes newer = before;
  putU32(newer, 8, PFX_SERIALIZE_VERSION + 1);
  PfxSerializedMeshes meshes;
  std::string error;
  EXPECT_EQ(loadWorld(target.world, meshes, newer, &error), PFX_ERR_INVALID_FLAG);
  EXPECT_NE(error.find("version: is " + std::to_string(PFX_SERIALIZE_VERSION + 1)),
            std::string::npos)
      << error;
  EXPECT_EQ(saveWorld(target.world), before);
  EXPECT_TRUE(meshes.largeMeshes().empty());
}

double readRealAt(const Bytes& bytes, std::size_t at, std::size_t realBytes) {
  if (realBytes == 4) {
    const PfxUInt32 bits = getU32(bytes, at);
    float f;
    std::memcpy(&f, &bits, 4);
    return f;
  }
  const PfxUInt64 bits = getU64(bytes, at);
  double d;
  std::memcpy(&d, &bits, 8);
  return d;
}

// Each build reads the file the other precision wrote of SmallWorld (tests/core/data;
// rewritten by a run with PFX_WRITE_SERIALIZE_FIXTURE=1), against SmallWorld built here:
// contacts, a coupled hinge, meshes of both kinds, and solver rows that hold the writer's
// largest value.
TEST(Serialize, ReadsTheOtherPrecisionsFileRoundingEachValueOnce) {
  constexpr bool kDouble = sizeof(PfxFloat) == 8;
  SmallWorld own;
  if (std::getenv("PFX_WRITE_SERIALIZE_FIXTURE")) {
    ASSERT_EQ(pfxSaveWorld(own.world, fixturePath(kDouble ? "double" : "float").c_str()), PFX_OK);
  }
  const std::string otherPath = fixturePath(kDouble ? "float" : "double");
  FilePtr file(std::fopen(otherPath.c_str(), "rb"));
  ASSERT_TRUE(file) << otherPath;
  const Bytes other = bytesOf(file.get());
  const std::size_t otherRealBytes = kDouble ? 4 : 8;
  ASSERT_EQ(other[12], otherRealBytes);

  PfxWorld loaded;
  PfxSerializedMeshes meshes;
  std::string error;
  ASSERT_EQ(loadWorld(loaded, meshes, other, &error), PFX_OK) << error;
  // Rounded once: the loaded time step is the file's value converted, nothing else.
  const std::size_t param = sectionPayload(other, "PARM");
  const double fileTimeStep = readRealAt(other, param + 9 * otherRealBytes, otherRealBytes);
  EXPECT_EQ(loaded.getParam().timeStep, static_cast<PfxFloat>(fileTimeStep));
  EXPECT_NE(double(loaded.getParam().timeStep), kDouble ? 1.0 / 60 : fileTimeStep)
      << "the value crossed precisions";
  // The same world within the other precision's round-off over 30 steps.
  ASSERT_EQ(loaded.getNumRigidBodies(), own.world.getNumRigidBodies());
  for (PfxUInt32 id = 0; id < loaded.getNumRigidBodies(); ++id) {
    const PfxRigidState& a = loaded.getRigidState(id);
    const PfxRigidState& b = own.world.getRigidState(id);
    EXPECT_LT((a.getPosition() - b.getPosition()).norm(), 1e-3) << "body " << id;
    EXPECT_EQ(a.getMotionType(), b.getMotionType());
    EXPECT_NEAR(loaded.getRigidBody(id).getMass(), own.world.getRigidBody(id).getMass(), 1e-6);
  }
  // Solver rows without an upper bound hold the writer's largest value; it arrives as ours.
  bool sawUnbounded = false;
  for (PfxUInt32 i = 0; i < loaded.getNumContactPairs(); ++i) {
    const PfxContactManifold& manifold = loaded.getContactManifold(loaded.getContactPair(i));
    for (PfxUInt32 k = 0; k < manifold.getNumContacts(); ++k) {
      const PfxFloat upper = manifold.getContactPoint(k).m_constraintRow[0].m_upperLimit;
      EXPECT_TRUE(std::isfinite(upper));
      if (upper == std::numeric_limits<PfxFloat>::max()) sawUnbounded = !kDouble;
      if (kDouble && upper == double(std::numeric_limits<float>::max())) sawUnbounded = true;
    }
  }
  EXPECT_TRUE(sawUnbounded);
  // The loaded world steps.
  for (int step = 0; step < 30; ++step) ASSERT_EQ(loaded.step(), PFX_OK);
}

}  // namespace
