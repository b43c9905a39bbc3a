// Between the bytes of a file and the application's arrays or world: the writer encodes
// arrays into bytes, the reader decodes and checks bytes into a PfxSerializeImage, from
// which pfxSerializeRead fills the application's buffers and pfxLoadWorld a world.
#pragma once

#include <cstdio>
#include <memory>
#include <vector>

#include "high_level/pfx_serialize_format.h"
#include "pfx/high_level/pfx_serialize.h"

namespace pfx {

// The ids of a world's removed bodies, joints and couplings, each list increasing.
struct PfxSerializeRemovals {
  std::vector<PfxUInt32> bodies;
  std::vector<PfxUInt32> joints;
  std::vector<PfxUInt32> couplings;
  bool empty() const { return bodies.empty() && joints.empty() && couplings.empty(); }
};

// A file's content, every value checked: ids within their arrays, meshes whole, nothing
// NaN. Shapes point to the meshes held here, which the image frees unless they are taken.
struct PfxSerializeImage {
  PfxSerializeImage() = default;
  ~PfxSerializeImage();
  PfxSerializeImage(const PfxSerializeImage&) = delete;
  PfxSerializeImage& operator=(const PfxSerializeImage&) = delete;

  PfxWorldParam param;
  double simulatedTime = 0;
  std::vector<PfxRigidState> states;
  std::vector<PfxRigidBody> bodies;
  std::vector<PfxVector3> forces;
  std::vector<PfxVector3> torques;
  std::vector<PfxShape> shapes;       // every body's, body after body
  std::vector<PfxUInt32> firstShape;  // per body, and the total at the end
  std::vector<PfxJoint> joints;
  std::vector<PfxJointCoupling> jointCouplings;
  std::vector<PfxUInt64> excludedPairKeys;
  std::vector<PfxContactManifold> manifolds;
  std::vector<PfxUInt32> freeManifolds;
  std::vector<PfxBroadphasePair> pairs;
  std::vector<PfxBroadphasePair> sleepingPairs;
  std::vector<PfxConvexMesh*> convexMeshes;
  std::vector<PfxLargeTriMesh*> largeMeshes;
  // PfxWorld's particle groups by id (null for a free id), from the optional section PART.
  std::vector<std::unique_ptr<PfxParticleGroup>> particleGroups;
  // The slots PfxWorld::removeRigidBody and removeJoint left, from the optional section GONE.
  PfxSerializeRemovals removals;

  PfxUInt32 numBodies() const { return static_cast<PfxUInt32>(states.size()); }
  // Counts as PfxSerializeCapacity names them (compound shapes only).
  PfxSerializeCapacity capacity() const;
};

// Encodes what the buffers name (header, sections, checksum) into `bytes`. Rejects null
// arrays where their count is not 0 (PFX_ERR_NULL_POINTER) and shapes without their mesh.
// A world's particle groups (null for a free id), written as the section PART after CONT
// when there is at least one; files without them stay as version 1 always wrote them.
PfxInt32 pfxEncodeSerialized(
    const PfxSerializeCapacity& counts, const PfxSerializeBuffer& buffer,
    std::vector<PfxUInt8>& bytes, PfxSerializeError& error,
    const std::vector<std::unique_ptr<PfxParticleGroup>>* particleGroups = nullptr,
    const PfxSerializeRemovals* removals = nullptr);

// The section PART, both ways (pfx_serialize_particles.cpp). The reader checks each group
// as PfxWorld::addParticleGroup would, against the bodies already read.
void pfxEncodeParticleGroups(PfxByteWriter& w,
                             const std::vector<std::unique_ptr<PfxParticleGroup>>& groups);
bool pfxDecodeParticleGroups(PfxByteReader& r, PfxSerializeImage& image);

// The section GONE, both ways (pfx_serialize_removals.cpp), written after CONT when a world
// has removed slots. The reader checks the ids against the counts read, that a removed
// body's slot is inert (fixed, contact filters 0), and that nothing alive names a removed
// slot: a joint, a coupling, a pair, an exclusion; pfxCheckRemovedPins does the particle
// groups once they are read.
void pfxEncodeRemovals(PfxByteWriter& w, const PfxSerializeRemovals& removals);
bool pfxDecodeRemovals(PfxByteReader& r, PfxSerializeImage& image);
bool pfxCheckRemovedPins(PfxByteReader& r, const PfxSerializeImage& image);

// Reads the header and the body it announces from the stream, and no further. The buffer
// grows only as bytes arrive, so a length the stream does not hold allocates nothing.
PfxInt32 pfxReadSerializedBytes(FILE* file, std::vector<PfxUInt8>& bytes, PfxSerializeError& error);

// Decodes and checks a whole file (header included) into `image`, reporting progress by
// section through `update` (may be null). On failure `image` may hold part of the file; its
// destructor frees what it allocated.
PfxInt32 pfxDecodeSerialized(const std::vector<PfxUInt8>& bytes, PfxSerializeImage& image,
                             PfxSerializeError& error, PfxSerializeUpdateFunc update,
                             void* userData);

// A world's contacts as a file holds them: every pair with a manifold of its own. The pairs
// that name the world's shared empty manifold (PfxWorld::settleManifolds) get empty ones,
// appended in pair order, awake pairs first; the shared one is written as the first free
// slot. Reading a world back undoes both (PfxSerializeAccess::restoreWorld).
struct PfxSerializeContacts {
  std::vector<PfxContactManifold> manifolds;
  std::vector<PfxUInt32> freeManifolds;
  std::vector<PfxBroadphasePair> pairs;
  std::vector<PfxBroadphasePair> sleepingPairs;
};

// The private state the serializer reads and restores (friend of PfxWorld,
// PfxContactManifold, PfxRigidState and PfxSerializedMeshes).
class PfxSerializeAccess {
 public:
  static void setSleep(PfxRigidState& state, bool asleep, PfxUInt16 sleepCount) {
    state.m_sleeping = asleep ? 1 : 0;
    state.m_sleepCount = sleepCount;
  }
  static void setNumContacts(PfxContactManifold& manifold, PfxUInt32 numContacts) {
    manifold.m_numContacts = numContacts;
  }
  static const std::vector<std::unique_ptr<PfxParticleGroup>>& particleGroups(
      const PfxWorld& world) {
    return world.m_particleGroups;
  }
  static PfxSerializeRemovals removals(const PfxWorld& world);
  static PfxInt32 checkWorldParam(const PfxWorldParam& param) {
    return PfxWorld::checkParam(param);
  }
  static PfxInt32 checkBody(const PfxRigidState& state, const PfxRigidBody& body) {
    return PfxWorld::validateBody(state, body);
  }
  // The world's arrays as the writer takes them (it finds the shapes through the
  // collidables); the contacts as the file holds them, in `contacts`.
  static void describeWorld(const PfxWorld& world, PfxSerializeCapacity& counts,
                            PfxSerializeBuffer& buffer, PfxWorldParam& param, double& time,
                            PfxSerializeContacts& contacts);
  // Replaces the world's content by the image's (already checked) and hands the meshes to
  // `meshes`. Cannot fail but for memory.
  static void restoreWorld(PfxWorld& world, PfxSerializeImage& image,
                           const PfxLoadWorldOptions& options, PfxSerializedMeshes& meshes);
};

}  // namespace pfx
