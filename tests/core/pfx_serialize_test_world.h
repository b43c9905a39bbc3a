// Worlds for the serialization tests, holding every kind of state a file carries, and the
// byte plumbing around pfxSaveWorld / pfxLoadWorld.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <vector>

#include "pfx/base_level/joint/pfx_joint_init.h"
#include "pfx/high_level/pfx_body_init.h"
#include "pfx/high_level/pfx_ragdoll.h"
#include "pfx/high_level/pfx_serialize.h"
#include "pfx/low_level/pfx_error_detail.h"
#include "pfx_large_mesh_test_util.h"
#include "pfx_test_meshes.h"

namespace pfx_test {

using namespace pfx;

using Bytes = std::vector<PfxUInt8>;

// A FILE* over bytes that closes itself.
struct FileCloser {
  void operator()(FILE* file) const { std::fclose(file); }
};
using FilePtr = std::unique_ptr<FILE, FileCloser>;

inline FilePtr fileWith(const Bytes& bytes) {
  FilePtr file(std::tmpfile());
  if (!bytes.empty()) std::fwrite(bytes.data(), 1, bytes.size(), file.get());
  std::rewind(file.get());
  return file;
}

inline Bytes bytesOf(FILE* file) {
  Bytes bytes;
  std::rewind(file);
  PfxUInt8 block[4096];
  for (std::size_t n; (n = std::fread(block, 1, sizeof(block), file)) > 0;) {
    bytes.insert(bytes.end(), block, block + n);
  }
  return bytes;
}

inline Bytes saveWorld(const PfxWorld& world) {
  FilePtr file(std::tmpfile());
  std::string error;
  EXPECT_EQ(pfxSaveWorld(world, file.get(), &error), PFX_OK) << error;
  return bytesOf(file.get());
}

inline PfxInt32 loadWorld(PfxWorld& world, PfxSerializedMeshes& meshes, const Bytes& bytes,
                          std::string* error = nullptr,
                          const PfxLoadWorldOptions& options = PfxLoadWorldOptions()) {
  FilePtr file = fileWith(bytes);
  return pfxLoadWorld(world, file.get(), meshes, error, options);
}

// The file's words, little-endian as the format stores them.
template <typename Word>
void putWord(Bytes& bytes, std::size_t at, Word v) {
  for (std::size_t i = 0; i < sizeof(Word); ++i) bytes[at + i] = PfxUInt8(v >> (8 * i));
}

template <typename Word>
Word getWord(const Bytes& bytes, std::size_t at) {
  Word v = 0;
  for (std::size_t i = 0; i < sizeof(Word); ++i) v |= Word(bytes[at + i]) << (8 * i);
  return v;
}

inline constexpr auto putU32 = putWord<PfxUInt32>;
inline constexpr auto getU32 = getWord<PfxUInt32>;
inline constexpr auto putU64 = putWord<PfxUInt64>;
inline constexpr auto getU64 = getWord<PfxUInt64>;

// The file format's checksum (README.md, "Serialization"): FNV-1a over the bytes after the
// 32-byte header, eight at a time as little-endian words and the last few one by one,
// stored at offset 24. Tests that alter a file on purpose set it again, so that the checks
// behind it are reached.
inline void resealChecksum(Bytes& bytes) {
  PfxUInt64 hash = 0xcbf29ce484222325ull;
  std::size_t i = 32;
  for (; i + 8 <= bytes.size(); i += 8) {
    hash ^= getU64(bytes, i);
    hash *= 0x100000001b3ull;
  }
  for (; i < bytes.size(); ++i) {
    hash ^= bytes[i];
    hash *= 0x100000001b3ull;
  }
  putU64(bytes, 24, hash);
}

// Offset of the payload of the section tagged `tag` (after its tag and length).
inline std::size_t sectionPayload(const Bytes& bytes, const char* tag) {
  std::size_t at = 32;
  while (at + 12 <= bytes.size()) {
    const PfxUInt64 length = getU64(bytes, at + 4);
    if (std::equal(tag, tag + 4, bytes.begin() + at)) return at + 12;
    at += 12 + length;
  }
  ADD_FAILURE() << "no section " << tag;
  return 0;
}

// What a world holds, body by body, for bit-for-bit comparisons.
inline bool sameStates(const PfxWorld& a, const PfxWorld& b) {
  if (a.getNumRigidBodies() != b.getNumRigidBodies()) return false;
  return std::memcmp(a.getRigidStates(), b.getRigidStates(),
                     sizeof(PfxRigidState) * a.getNumRigidBodies()) == 0;
}

// The mixed world of the resume test: a box pyramid and a pile that falls asleep on a
// fixed ground, a chain of capsules under a heavy ball swinging from a fixed anchor, two
// pendulums whose hinges are coupled, a ragdoll, convex hulls sharing one mesh and a
// compound tumbling on a quantized terrain, balls on a mesh that deforms, a keyframe
// paddle, collision exclusions and forces applied between steps.
struct MixedWorld {
  PfxWorld world;
  MeshSource terrainSource;
  MeshSource deformSource;
  MeshOwner terrain;
  MeshOwner deform;
  PfxConvexMesh hull{};
  PfxUInt32 deformBody = 0;
  PfxUInt32 keyframeBody = 0;
  PfxUInt32 pushedBody = 0;
};

inline PfxUInt32 addBody(PfxWorld& world, const PfxShape& shape, const PfxVector3& position,
                         PfxFloat mass, PfxMotionType type = kPfxMotionTypeActive) {
  PfxBodyInit init;
  init.position = position;
  init.mass = mass;
  init.motionType = type;
  PfxUInt32 id = 0;
  EXPECT_EQ(pfxAddBody(world, shape, init, &id), PFX_OK);
  return id;
}

inline PfxUInt32 addMeshBody(PfxWorld& world, const PfxLargeTriMesh* mesh,
                             const PfxVector3& position) {
  PfxShape shape;
  shape.reset();
  shape.setLargeTriMesh(mesh);
  return addBody(world, shape, position, 0);
}

inline void buildMixedWorld(MixedWorld& m, PfxUInt32 numThreads) {
  PfxWorldParam param;
  param.numThreads = numThreads;
  ASSERT_EQ(m.world.initialize(param), PFX_OK);
  PfxWorld& world = m.world;

  // Fixed ground for the pyramid, the pile and the chain.
  addBody(world, pfxMakeShape(PfxBox(6, 0.5f, 6)), PfxVector3(-7, -0.5f, 0), 0);
  for (int level = 0; level < 4; ++level) {
    for (int i = 0; i < 4 - level; ++i) {
      addBody(world, pfxMakeShape(PfxBox(0.25f, 0.25f, 0.25f)),
              PfxVector3(-11 + 0.52f * i + 0.26f * level, 0.25f + 0.5f * level, -3), 1);
    }
  }
  std::vector<PfxUInt32> pile;
  for (int i = 0; i < 6; ++i) {
    pile.push_back(addBody(world, pfxMakeShape(PfxBox(0.3f, 0.15f, 0.2f)),
                           PfxVector3(-4 + 0.05f * i, 0.2f + 0.32f * i, 3), 2));
  }
  EXPECT_EQ(world.excludeCollision(pile[4], pile[5]), PFX_OK);
  m.pushedBody = pile[0];

  // A chain of five capsules from an anchor, started horizontal, ending in a 40 kg ball.
  const PfxUInt32 anchor =
      addBody(world, pfxMakeShape(PfxBox(0.1f, 0.1f, 0.1f)), PfxVector3(-7, 5, -3), 0);
  PfxUInt32 previous = anchor;
  PfxVector3 joint(-7, 5, -3);
  for (int i = 0; i < 6; ++i) {
    const bool payload = i == 5;
    const PfxVector3 centre = joint + PfxVector3(payload ? 0.3f : 0.25f, 0, 0);
    PfxBodyInit init;
    init.position = centre;
    init.mass = payload ? 40 : 1;
    PfxShape shape =
        payload ? pfxMakeShape(PfxSphere(0.3f)) : pfxMakeShape(PfxCapsule(0.15f, 0.05f));
    PfxUInt32 id = 0;
    EXPECT_EQ(pfxAddBody(world, shape, init, &id), PFX_OK);
    PfxBallJointInitParam ball;
    ball.anchorPoint = joint;
    PfxJoint j;
    EXPECT_EQ(
        pfxInitializeBallJoint(j, world.getRigidState(previous), world.getRigidState(id), ball),
        PFX_OK);
    EXPECT_EQ(world.addJoint(j), PFX_OK);
    previous = id;
    joint += PfxVector3(0.5f, 0, 0);
  }

  // Two pendulums on hinges about Z, the second following the first backwards.
  PfxUInt32 hinges[2];
  for (int i = 0; i < 2; ++i) {
    const PfxVector3 pivot(-2.5f, 3, -5 + 1.0f * i);
    const PfxUInt32 base = addBody(world, pfxMakeShape(PfxBox(0.05f, 0.05f, 0.05f)), pivot, 0);
    const PfxUInt32 bar =
        addBody(world, pfxMakeShape(PfxBox(0.4f, 0.05f, 0.05f)), pivot + PfxVector3(0.4f, 0, 0), 1);
    PfxHingeJointInitParam hinge;
    hinge.anchorPoint = pivot;
    hinge.axis = PfxVector3::UnitZ();
    PfxJoint j;
    EXPECT_EQ(
        pfxInitializeHingeJoint(j, world.getRigidState(base), world.getRigidState(bar), hinge),
        PFX_OK);
    EXPECT_EQ(world.addJoint(j, &hinges[i]), PFX_OK);
  }
  PfxJointCoupling coupling;
  coupling.reset();
  coupling.m_leaderJointId = hinges[0];
  coupling.m_followerJointId = hinges[1];
  coupling.m_leaderAxis = kPfxJointAxisTwist;
  coupling.m_followerAxis = kPfxJointAxisTwist;
  coupling.m_multiplier = -1;
  EXPECT_EQ(world.addJointCoupling(coupling), PFX_OK);

  // A quantized terrain with bumps, a ragdoll, three hulls of one mesh and a compound.
  m.terrainSource = makeHeightField(16, 16, 0.75f, [](PfxFloat x, PfxFloat z) {
    return PfxFloat(0.3) * std::sin(x) * std::cos(PfxFloat(0.7) * z);
  });
  ASSERT_EQ(pfxCreateLargeTriMesh(
                m.terrain.mesh,
                m.terrainSource.param(PFX_MESH_FLAG_USE_QUANTIZED | PFX_MESH_FLAG_USE_BVH)),
            PFX_OK);
  addMeshBody(world, &m.terrain.mesh, PfxVector3(6, 0, 0));
  PfxRagdoll ragdoll;
  ASSERT_EQ(pfxAddRagdoll(world, PfxVector3(6, 1.6f, 0), PfxQuat::Identity(), &ragdoll), PFX_OK);
  const TriangleList box = makeBoxTriangles(0.2f, 0.15f, 0.1f);
  ASSERT_EQ(pfxCreateConvexMesh(m.hull, box.vertices.data(), box.numVertices(), box.indices.data(),
                                box.numIndices()),
            PFX_OK);
  for (int i = 0; i < 3; ++i) {
    addBody(world, pfxMakeShape(&m.hull), PfxVector3(3 + 1.2f * i, 1.0f + 0.3f * i, 3), 1);
  }
  PfxShape compound[2] = {pfxMakeShape(PfxBox(0.2f, 0.1f, 0.1f)), pfxMakeShape(PfxSphere(0.12f))};
  compound[0].setOffsetPosition(PfxVector3(-0.1f, 0, 0));
  compound[1].setOffsetPosition(PfxVector3(0.2f, 0, 0));
  PfxBodyInit compoundInit;
  compoundInit.position = PfxVector3(9, 1.2f, -3);
  compoundInit.angularVelocity = PfxVector3(0, 1, 2);
  EXPECT_EQ(pfxAddBody(world, compound, 2, compoundInit), PFX_OK);

  // A mesh that deforms under three balls.
  m.deformSource = makeFlatGrid(6, 0.5f);
  ASSERT_EQ(pfxCreateLargeTriMesh(m.deform.mesh, m.deformSource.param(0)), PFX_OK);
  m.deformBody = addMeshBody(world, &m.deform.mesh, PfxVector3(6, 0, 10));
  for (int i = 0; i < 3; ++i) {
    addBody(world, pfxMakeShape(PfxSphere(0.2f)), PfxVector3(5.4f + 0.6f * i, 0.25f, 10), 1);
  }

  // A keyframe paddle sweeping through the pile's side.
  m.keyframeBody = addBody(world, pfxMakeShape(PfxBox(0.1f, 0.3f, 0.6f)),
                           PfxVector3(-2.5f, 0.3f, 3), 1, kPfxMotionTypeKeyframe);
}

// What the application does between steps, the same in the saved and the loaded world:
// deforms the mesh, moves the paddle and now and then pushes a box of the pile.
inline void driveMixedWorld(PfxWorld& world, const MixedWorld& m, PfxLargeTriMesh& deformMesh,
                            int step) {
  if (step % 15 == 0) {
    std::vector<PfxFloat> vertices = m.deformSource.vertices;
    for (std::size_t v = 0; v < vertices.size(); v += 3) {
      vertices[v + 1] = PfxFloat(0.08) * std::sin(PfxFloat(0.02) * step + vertices[v]);
    }
    ASSERT_EQ(world.updateLargeTriMesh(m.deformBody, deformMesh, vertices.data(),
                                       m.deformSource.numVertices()),
              PFX_OK);
  }
  const PfxFloat t = PfxFloat(step) / 60;
  const PfxVector3 paddle(-2.5f + 0.8f * std::sin(0.5f * t), 0.3f, 3);
  ASSERT_EQ(
      world.setKeyframeTarget(m.keyframeBody, paddle,
                              PfxQuat(Eigen::AngleAxis<PfxFloat>(0.3f * t, PfxVector3::UnitY()))),
      PFX_OK);
  if (step % 70 == 0) {
    ASSERT_EQ(world.applyForce(m.pushedBody, PfxVector3(0, 0, 150), PfxVector3(0, 5, 0)), PFX_OK);
  }
}

// A small world with one of everything a file holds: fixed ground, a hull, a quantized
// mesh (16-bit corners) with a ball asleep on it, an array mesh (32-bit corners), a hinge
// pendulum coupled to another, an exclusion, a pending force, contact pairs awake and asleep.
struct SmallWorld {
  PfxWorld world;
  MeshSource quantizedSource = makeFlatGrid(3, 1);
  MeshSource arraySource = makeFlatGrid(2, 1);
  MeshOwner quantized;
  MeshOwner array;
  PfxConvexMesh hull{};

  SmallWorld() {
    EXPECT_EQ(
        pfxCreateLargeTriMesh(quantized.mesh, quantizedSource.param(PFX_MESH_FLAG_USE_QUANTIZED)),
        PFX_OK);
    EXPECT_EQ(pfxCreateLargeTriMesh(array.mesh, arraySource.param(PFX_MESH_FLAG_USE_BVH)), PFX_OK);
    const TriangleList box = makeBoxTriangles(0.2f, 0.2f, 0.2f);
    EXPECT_EQ(pfxCreateConvexMesh(hull, box.vertices.data(), box.numVertices(), box.indices.data(),
                                  box.numIndices()),
              PFX_OK);
    addBody(world, pfxMakeShape(PfxBox(2, 0.5f, 2)), PfxVector3(0, -0.5f, 0), 0);
    PfxBodyInit rolling;
    rolling.position = PfxVector3(-1.5f, 0.2f, -1.5f);
    rolling.linearVelocity = PfxVector3(1, 0, 0);
    EXPECT_EQ(pfxAddBody(world, pfxMakeShape(PfxSphere(0.2f)), rolling), PFX_OK);
    addBody(world, pfxMakeShape(&hull), PfxVector3(-1, 0.2f, 0), 1);
    const PfxUInt32 a =
        addBody(world, pfxMakeShape(PfxSphere(0.2f)), PfxVector3(-1.5f, 0.2f, 1), 1);
    const PfxUInt32 b =
        addBody(world, pfxMakeShape(PfxSphere(0.2f)), PfxVector3(-1.1f, 0.2f, 1), 1);
    EXPECT_EQ(world.excludeCollision(a, b), PFX_OK);
    addMeshBody(world, &quantized.mesh, PfxVector3(5, 0, 0));
    addBody(world, pfxMakeShape(PfxSphere(0.2f)), PfxVector3(5, 0.2f, 0), 1);
    addMeshBody(world, &array.mesh, PfxVector3(-5, 0, 5));
    PfxUInt32 hinges[2];
    for (int i = 0; i < 2; ++i) {
      const PfxVector3 pivot(1, 2, -1.0f + i);
      const PfxUInt32 base = addBody(world, pfxMakeShape(PfxBox(0.05f, 0.05f, 0.05f)), pivot, 0);
      const PfxUInt32 bar = addBody(world, pfxMakeShape(PfxBox(0.3f, 0.05f, 0.05f)),
                                    pivot + PfxVector3(0.3f, 0, 0), 1);
      PfxHingeJointInitParam hinge;
      hinge.anchorPoint = pivot;
      PfxJoint joint;
      EXPECT_EQ(pfxInitializeHingeJoint(joint, world.getRigidState(base), world.getRigidState(bar),
                                        hinge),
                PFX_OK);
      EXPECT_EQ(world.addJoint(joint, &hinges[i]), PFX_OK);
    }
    PfxJointCoupling coupling;
    coupling.reset();
    coupling.m_leaderJointId = hinges[0];
    coupling.m_followerJointId = hinges[1];
    coupling.m_leaderAxis = coupling.m_followerAxis = kPfxJointAxisTwist;
    EXPECT_EQ(world.addJointCoupling(coupling), PFX_OK);
    for (int step = 0; step < 60; ++step) EXPECT_EQ(world.step(), PFX_OK);
    EXPECT_GT(world.getStats().numSleepingPairs, 0u);
    EXPECT_GT(world.getStats().numPairs, 0u);
    EXPECT_EQ(world.applyForce(1, PfxVector3(1, 0, 0), PfxVector3::Zero()), PFX_OK);
  }
};

}  // namespace pfx_test
