// Serialization (seed chapter 7): a world's instances written to a FILE* and read back, on
// this or any other platform, in float or double (the format is described in README.md,
// "Serialization").
//
// Two levels, one reader and one writer under both:
//   - the seed's pfxSerializeWrite / pfxSerializeRead over the application's arrays, which
//     an initialization callback names (PfxSerializeBuffer) and sizes (PfxSerializeCapacity);
//   - pfxSaveWorld / pfxLoadWorld for a whole PfxWorld, its private state included, so that
//     a loaded world continues bit for bit where the saved one stood.
//
// Reading checks everything before it stores anything: a file that is cut short, altered,
// of a newer version, or that names bodies, meshes or manifolds it does not hold ends in
// the error callback with the tags of the place (e.g. "bodies", "body 12", "state") and
// an error code, and the application's buffers or world are left as they were. Nothing is
// allocated for a count the rest of the file cannot hold. Files are neither opened nor
// closed here.
#pragma once

#include <cstdio>
#include <string>
#include <vector>

#include "pfx/base_level/base/pfx_utility_allocator.h"
#include "pfx/base_level/collision/pfx_convex_mesh.h"
#include "pfx/base_level/collision/pfx_large_tri_mesh.h"
#include "pfx/high_level/pfx_world.h"

namespace pfx {

// Version of the format this build writes. It reads every version from the first to this
// one, taking the defaults of PfxWorldParam for what an older file lacks, and refuses a
// newer one, whose fields it could not know.
constexpr PfxUInt32 PFX_SERIALIZE_VERSION = 3;
constexpr PfxUInt32 PFX_SERIALIZE_OLDEST_VERSION = 1;

// How many of each instance a buffer holds (the initialization callback sets it), and on
// return how many were written or read (the termination callback receives it).
struct PfxSerializeCapacity {
  // States, bodies, collidables and pending forces and torques: one of each per body.
  PfxUInt32 numRigidBodies = 0;
  // Shapes of compound collidables (more than one shape), which the collidables read refer
  // to. Read only: a write takes the shapes from the collidables.
  PfxUInt32 numShapes = 0;
  PfxUInt32 numJoints = 0;
  PfxUInt32 numJointCouplings = 0;
  // Pairs whose bodies are awake, sorted by key, and pairs set aside while all their bodies
  // sleep (or are fixed), sorted by key, as PfxWorld keeps them.
  PfxUInt32 numContactPairs = 0;
  PfxUInt32 numSleepingPairs = 0;
  // The manifold array that pairs index, and the indices of its unused slots.
  PfxUInt32 numContactManifolds = 0;
  PfxUInt32 numFreeManifolds = 0;
  // Body pairs that never collide (pfxCreatePairKey(idA, idB), idA < idB, sorted).
  PfxUInt32 numExcludedPairs = 0;
  // Read only: meshes the read allocated (each mesh of the file once, however many shapes
  // name it). A write finds the meshes through the shapes.
  PfxUInt32 numConvexMeshes = 0;
  PfxUInt32 numLargeMeshes = 0;
};

// The application's arrays, each holding the count of PfxSerializeCapacity that its
// comment names. A pointer may be null only where its count is 0; worldParam and
// simulatedTime are always required.
struct PfxSerializeBuffer {
  PfxWorldParam* worldParam = nullptr;
  double* simulatedTime = nullptr;                 // seconds
  PfxRigidState* rigidStates = nullptr;            // numRigidBodies
  PfxRigidBody* rigidBodies = nullptr;             // numRigidBodies
  PfxCollidable* collidables = nullptr;            // numRigidBodies
  PfxVector3* forces = nullptr;                    // numRigidBodies: applied during the next step
  PfxVector3* torques = nullptr;                   // numRigidBodies
  PfxShape* shapes = nullptr;                      // numShapes
  PfxUInt16* shapeIds = nullptr;                   // numShapes
  PfxJoint* joints = nullptr;                      // numJoints
  PfxJointCoupling* jointCouplings = nullptr;      // numJointCouplings
  PfxBroadphasePair* contactPairs = nullptr;       // numContactPairs
  PfxBroadphasePair* sleepingPairs = nullptr;      // numSleepingPairs
  PfxContactManifold* contactManifolds = nullptr;  // numContactManifolds
  PfxUInt32* freeManifolds = nullptr;              // numFreeManifolds
  PfxUInt64* excludedPairKeys = nullptr;           // numExcludedPairs
  // Read only: where the read stores the meshes it allocated. The application owns them
  // then and frees them with pfxDeleteConvexMesh / pfxDeleteLargeTriMesh.
  PfxConvexMesh** convexMeshes = nullptr;   // numConvexMeshes
  PfxLargeTriMesh** largeMeshes = nullptr;  // numLargeMeshes
};

// Initialization (required): sets the counts to write, or the capacities to read into, and
// the arrays. Returning false stops the call (PFX_ERR_OUT_OF_BUFFER) before anything is
// written or read.
using PfxSerializeInitFunc = bool (*)(PfxSerializeCapacity& capacity, PfxSerializeBuffer& buffer,
                                      void* userData);
// Termination (optional): called once the call has succeeded, with what was written or read.
using PfxSerializeTermFunc = void (*)(const PfxSerializeCapacity& counts,
                                      const PfxSerializeBuffer& buffer, void* userData);
// Buffer resizing (read only, optional): the file holds more than `capacity`; make room
// for `capacityLoaded` (reallocate the arrays short of it, point `buffer` at them, update
// `capacity`) and return true. False, or no callback, fails the read
// (PFX_ERR_OUT_OF_BUFFER) with the buffers unchanged.
using PfxSerializeResizeFunc = bool (*)(PfxSerializeCapacity& capacity, PfxSerializeBuffer& buffer,
                                        const PfxSerializeCapacity& capacityLoaded, void* userData);
// Update (read only, optional): progress while the file is parsed, in bytes.
using PfxSerializeUpdateFunc = void (*)(PfxUInt64 bytesDone, PfxUInt64 bytesTotal, void* userData);
// Error (optional): the error code, and the tags from the outermost to the innermost that
// locate the failure in the file (none for an error outside it, such as a null argument).
// pfxGetLastErrorDetail() has the same, as one line with the reason.
using PfxSerializeErrorFunc = void (*)(PfxInt32 errorCode, const char* const* tags,
                                       PfxUInt32 numTags, void* userData);

struct PfxSerializeCallbacks {
  PfxSerializeInitFunc init = nullptr;
  PfxSerializeTermFunc term = nullptr;
  PfxSerializeResizeFunc resize = nullptr;  // read only
  PfxSerializeUpdateFunc update = nullptr;  // read only
  PfxSerializeErrorFunc error = nullptr;
  void* userData = nullptr;
};

// Writes what the buffers hold, in the build's precision. Rejects a null file or init
// callback and null arrays (PFX_ERR_NULL_POINTER), and anything the read would reject
// (invalid states, ids out of range, NaN, ...: the same codes and tags), before writing a
// byte; a failing stream gives PFX_ERR_OUT_OF_BUFFER.
PfxInt32 pfxSerializeWrite(FILE* file, const PfxSerializeCallbacks& callbacks);

// Reads a file that pfxSerializeWrite wrote, in either precision (values are rounded once
// to this build's PfxFloat; a double beyond float's range becomes the largest float).
// Compound collidables refer to buffer.shapes and buffer.shapeIds; shapes refer to the
// meshes stored in buffer.convexMeshes and buffer.largeMeshes. Errors: PFX_ERR_NULL_POINTER
// (file, init callback, an array), PFX_ERR_INVALID_FLAG (not this format, a newer version,
// an unknown enum), PFX_ERR_OUT_OF_BUFFER (cut short, or a buffer too small and not
// resized), PFX_ERR_OUT_OF_RANGE (an index or count outside its limit),
// PFX_ERR_INVALID_VALUE (bytes that no longer match the file's checksum, NaN, infinity, or
// a value the world would reject).
PfxInt32 pfxSerializeRead(FILE* file, const PfxSerializeCallbacks& callbacks);

// The meshes a pfxLoadWorld allocated, which the loaded world's shapes point to: keep this
// alive as long as the world. Freed with it.
class PfxSerializedMeshes {
 public:
  PfxSerializedMeshes() = default;
  ~PfxSerializedMeshes() { clear(); }
  PfxSerializedMeshes(PfxSerializedMeshes&& other) noexcept;
  PfxSerializedMeshes& operator=(PfxSerializedMeshes&& other) noexcept;
  PfxSerializedMeshes(const PfxSerializedMeshes&) = delete;
  PfxSerializedMeshes& operator=(const PfxSerializedMeshes&) = delete;

  // In the order the file stores them: the order in which the saved world's bodies first
  // named them. A deforming mesh is passed to PfxWorld::updateLargeTriMesh from here.
  const std::vector<PfxConvexMesh*>& convexMeshes() const { return m_convexMeshes; }
  const std::vector<PfxLargeTriMesh*>& largeMeshes() const { return m_largeMeshes; }
  // Frees every mesh (the world that used them must not step again).
  void clear();

 private:
  friend class PfxSerializeAccess;
  std::vector<PfxConvexMesh*> m_convexMeshes;
  std::vector<PfxLargeTriMesh*> m_largeMeshes;
};

// Saves the whole world: parameters, simulated time, bodies, shapes and meshes (each mesh
// once), joints, couplings, exclusions, contact pairs and manifolds with their impulses,
// sleep, pending forces and keyframe motion. `error` (optional) receives the reason of a
// failure, starting with the tags of the place. Particle groups (with their ids, sleep and
// the particles' velocities) go in the optional section PART; a world without them writes
// the same bytes as before, and files without PART load as before. pfxSerializeRead, which
// has no buffers for particle groups, refuses a file holding them (PFX_ERR_OUT_OF_BUFFER).
PfxInt32 pfxSaveWorld(const PfxWorld& world, FILE* file, std::string* error = nullptr);
PfxInt32 pfxSaveWorld(const PfxWorld& world, const char* path, std::string* error = nullptr);
// The same bytes as pfxSaveWorld writes, in memory (to copy a world, or send it to another
// process). On failure `bytes` is unchanged.
PfxInt32 pfxSaveWorldToBytes(const PfxWorld& world, std::vector<PfxUInt8>& bytes,
                             std::string* error = nullptr);

struct PfxLoadWorldOptions {
  // The saved PfxWorldParam::numThreads is the saving machine's choice; a thread count
  // does not change the results (PfxWorldParam::numThreads).
  bool keepSavedNumThreads = true;
  PfxUInt32 numThreads = 1;  // used when keepSavedNumThreads is false
};

// Replaces everything `world` holds with the saved world, which then steps exactly as the
// saved one would have. On success `meshes` is cleared first and then owns the loaded
// meshes. On failure the world and `meshes` are unchanged, nothing stays allocated, and
// `error` (optional) receives the tags of the place and the reason, for example
// "bodies/body 12/state: orientation is not a unit quaternion".
PfxInt32 pfxLoadWorld(PfxWorld& world, FILE* file, PfxSerializedMeshes& meshes,
                      std::string* error = nullptr,
                      const PfxLoadWorldOptions& options = PfxLoadWorldOptions());
PfxInt32 pfxLoadWorld(PfxWorld& world, const char* path, PfxSerializedMeshes& meshes,
                      std::string* error = nullptr,
                      const PfxLoadWorldOptions& options = PfxLoadWorldOptions());
// As pfxLoadWorld, from the `size` bytes at `data` (pfxSaveWorldToBytes' or a file's), which
// must hold exactly one world: bytes past its end are refused, not ignored.
PfxInt32 pfxLoadWorldFromBytes(PfxWorld& world, const PfxUInt8* data, std::size_t size,
                               PfxSerializedMeshes& meshes, std::string* error = nullptr,
                               const PfxLoadWorldOptions& options = PfxLoadWorldOptions());

}  // namespace pfx
