// A whole PfxWorld saved and loaded through the same writer and reader as the seed's
// entry points, private state included: the pairs of the last step with their manifolds
// and the order of the free manifold slots (the next new pair takes the last one), so that
// the loaded world steps bit for bit as the saved one.
#include <algorithm>
#include <cerrno>
#include <cstring>

#include "high_level/pfx_serialize_image.h"
#include "low_level/pfx_param_checks.h"

namespace pfx {

namespace {

PfxInt32 fail(const char* function, const PfxSerializeError& error, std::string* message) {
  if (message) *message = error.describe();
  return pfxRejectParam(error.code, "%s: %s", function, error.describe().c_str());
}

// A null file, path or buffer: `what` names it.
PfxInt32 failNull(const char* function, const char* what, std::string* message) {
  PfxSerializeError error;
  error.code = PFX_ERR_NULL_POINTER;
  error.reason = std::string(what) + " is null";
  return fail(function, error, message);
}

// The message leaves the path to the caller, who named it; the error detail names it.
PfxInt32 failOpen(const char* function, const char* path, const char* mode, std::string* message) {
  if (!path) return failNull(function, "the path", message);
  const std::string reason =
      std::string("cannot be opened for ") + mode + ": " + std::strerror(errno);
  if (message) *message = reason;
  return pfxRejectParam(PFX_ERR_INVALID_VALUE, "%s: '%s' %s", function, path, reason.c_str());
}

// The pairs naming the world's shared empty manifold, each given an empty one of its own
// at the end of `manifolds` (PfxSerializeContacts).
void giveSharingPairsTheirOwn(std::vector<PfxBroadphasePair>& pairs, PfxUInt32 sharedId,
                              std::vector<PfxContactManifold>& manifolds) {
  for (PfxBroadphasePair& pair : pairs) {
    if (pfxGetContactId(pair) != sharedId) continue;
    pfxSetContactId(pair, static_cast<PfxUInt32>(manifolds.size()));
    manifolds.emplace_back().reset(pfxGetObjectIdA(pair), pfxGetObjectIdB(pair));
  }
}

// The file's empty manifolds at the end of the slots, each a pair's, go back to being the
// shared empty one: the first free slot, or a new one when none is free. Others stay the
// pairs' own (a file may hold them; the next step gives them back).
PfxUInt32 shareTrailingEmptyManifolds(PfxSerializeImage& image) {
  std::vector<PfxBroadphasePair*> namedBy(image.manifolds.size(), nullptr);
  for (auto* pairs : {&image.pairs, &image.sleepingPairs}) {
    for (PfxBroadphasePair& pair : *pairs) namedBy[pfxGetContactId(pair)] = &pair;
  }
  std::vector<PfxBroadphasePair*> sharing;
  while (!image.manifolds.empty() && namedBy[image.manifolds.size() - 1] &&
         image.manifolds.back().getNumContacts() == 0) {
    sharing.push_back(namedBy[image.manifolds.size() - 1]);
    image.manifolds.pop_back();
  }
  PfxUInt32 sharedId = static_cast<PfxUInt32>(image.manifolds.size());
  if (image.freeManifolds.empty()) {
    image.manifolds.emplace_back().reset(0, 0);
  } else {
    sharedId = image.freeManifolds.front();
    image.freeManifolds.erase(image.freeManifolds.begin());
  }
  for (PfxBroadphasePair* pair : sharing) pfxSetContactId(*pair, sharedId);
  return sharedId;
}

}  // namespace

void PfxSerializeAccess::describeWorld(const PfxWorld& world, PfxSerializeCapacity& counts,
                                       PfxSerializeBuffer& buffer, PfxWorldParam& param,
                                       double& time, PfxSerializeContacts& contacts) {
  // The buffer's pointers are not const as a read fills them; the writer only reads.
  PfxWorld& w = const_cast<PfxWorld&>(world);
  param = w.m_param;
  time = w.m_simulatedTime;
  counts.numRigidBodies = w.getNumRigidBodies();
  counts.numJoints = w.getNumJoints();
  counts.numJointCouplings = w.getNumJointCouplings();
  counts.numContactPairs = w.m_numPairs;
  counts.numSleepingPairs = w.m_numSleepingPairs;
  contacts.pairs.assign(w.m_pairs.begin(), w.m_pairs.begin() + w.m_numPairs);
  contacts.sleepingPairs.assign(w.m_sleepingPairs.begin(),
                                w.m_sleepingPairs.begin() + w.m_numSleepingPairs);
  contacts.manifolds = w.m_manifolds;
  giveSharingPairsTheirOwn(contacts.pairs, w.m_sharedEmptyManifold, contacts.manifolds);
  giveSharingPairsTheirOwn(contacts.sleepingPairs, w.m_sharedEmptyManifold, contacts.manifolds);
  contacts.freeManifolds.assign(1, w.m_sharedEmptyManifold);
  contacts.freeManifolds.insert(contacts.freeManifolds.end(), w.m_freeManifolds.begin(),
                                w.m_freeManifolds.end());
  counts.numContactManifolds = static_cast<PfxUInt32>(contacts.manifolds.size());
  counts.numFreeManifolds = static_cast<PfxUInt32>(contacts.freeManifolds.size());
  counts.numExcludedPairs = static_cast<PfxUInt32>(w.m_excludedPairKeys.size());
  buffer.worldParam = &param;
  buffer.simulatedTime = &time;
  buffer.rigidStates = w.m_states.data();
  buffer.rigidBodies = w.m_bodies.data();
  buffer.collidables = w.m_collidables.data();
  buffer.forces = w.m_forces.data();
  buffer.torques = w.m_torques.data();
  buffer.joints = w.m_joints.data();
  buffer.jointCouplings = w.m_jointCouplings.data();
  buffer.contactPairs = contacts.pairs.data();
  buffer.sleepingPairs = contacts.sleepingPairs.data();
  buffer.contactManifolds = contacts.manifolds.data();
  buffer.freeManifolds = contacts.freeManifolds.data();
  buffer.excludedPairKeys = w.m_excludedPairKeys.data();
}

void PfxSerializeAccess::restoreWorld(PfxWorld& world, PfxSerializeImage& image,
                                      const PfxLoadWorldOptions& options,
                                      PfxSerializedMeshes& meshes) {
  PfxWorldParam param = image.param;
  if (!options.keepSavedNumThreads) param.numThreads = options.numThreads;
  world.initialize(param);
  world.m_simulatedTime = image.simulatedTime;

  const PfxUInt32 numBodies = image.numBodies();
  world.reserveBodies(numBodies, numBodies);
  for (PfxUInt32 id = 0; id < numBodies; ++id) {
    const PfxUInt32 first = image.firstShape[id];
    const PfxUInt32 count = image.firstShape[id + 1] - first;
    // As addRigidBody builds it: one shape in the collidable, or a compound in its own block.
    PfxCollidable collidable;
    std::unique_ptr<PfxShape[]> compound;
    std::unique_ptr<PfxUInt16[]> compoundIds;
    if (count == 1) {
      collidable.reset();
    } else {
      compound.reset(new PfxShape[count]);
      compoundIds.reset(new PfxUInt16[count]);
      for (PfxUInt32 i = 0; i < count; ++i) compoundIds[i] = static_cast<PfxUInt16>(i);
      collidable.reset(compound.get(), compoundIds.get(), count);
    }
    for (PfxUInt32 i = 0; i < count; ++i) collidable.addShape(image.shapes[first + i]);
    collidable.finish();
    world.m_states.push_back(image.states[id]);
    world.m_bodies.push_back(image.bodies[id]);
    world.m_collidables.push_back(collidable);
    world.m_forces.push_back(image.forces[id]);
    world.m_torques.push_back(image.torques[id]);
    world.m_compoundShapes.push_back(std::move(compound));
    world.m_compoundShapeIds.push_back(std::move(compoundIds));
    if (image.states[id].isAsleep()) ++world.m_numSleepingBodies;
  }
  world.sizeBodyArraysToCapacity();

  world.m_removedBodies.assign(numBodies, 0);
  world.m_removedJoints.assign(image.joints.size(), 0);
  world.m_removedCouplings.assign(image.jointCouplings.size(), 0);
  for (const PfxUInt32 id : image.removals.bodies) world.m_removedBodies[id] = 1;
  for (const PfxUInt32 id : image.removals.joints) world.m_removedJoints[id] = 1;
  for (const PfxUInt32 id : image.removals.couplings) world.m_removedCouplings[id] = 1;
  world.m_numRemovedBodies = static_cast<PfxUInt32>(image.removals.bodies.size());
  world.m_numRemovedJoints = static_cast<PfxUInt32>(image.removals.joints.size());

  world.m_joints = image.joints;
  world.m_jointPairs.resize(world.m_joints.size());
  for (PfxUInt32 id = 0; id < world.m_joints.size(); ++id) {
    if (world.m_removedJoints[id]) continue;
    const PfxJoint& joint = world.m_joints[id];
    world.m_jointedPairKeys.push_back(
        pfxCreatePairKey(std::min(joint.m_rigidBodyIdA, joint.m_rigidBodyIdB),
                         std::max(joint.m_rigidBodyIdA, joint.m_rigidBodyIdB)));
  }
  std::sort(world.m_jointedPairKeys.begin(), world.m_jointedPairKeys.end());
  world.m_jointCouplings = image.jointCouplings;
  world.m_excludedPairKeys = image.excludedPairKeys;

  world.m_sharedEmptyManifold = shareTrailingEmptyManifolds(image);
  world.adoptManifolds(image.manifolds);
  world.m_freeManifolds.reserve(world.m_manifolds.capacity());
  world.m_freeManifolds = image.freeManifolds;
  world.m_numPairs = static_cast<PfxUInt32>(image.pairs.size());
  world.m_numSleepingPairs = static_cast<PfxUInt32>(image.sleepingPairs.size());
  world.reservePairs();
  std::copy(image.pairs.begin(), image.pairs.end(), world.m_pairs.begin());
  std::copy(image.sleepingPairs.begin(), image.sleepingPairs.end(), world.m_sleepingPairs.begin());
  world.countSleepingContacts();
  world.generateIslands();

  // Groups by id: a free id is held by a placeholder while the later groups are added, so
  // that every group keeps its id. The reader checked each group as addParticleGroup does.
  const PfxParticle placeholderParticle;
  PfxParticleGroupDesc placeholder;
  placeholder.particles = &placeholderParticle;
  placeholder.numParticles = 1;
  for (const auto& group : image.particleGroups) {
    world.addParticleGroup(group ? group->desc() : placeholder);
  }
  for (PfxUInt32 id = 0; id < image.particleGroups.size(); ++id) {
    if (!image.particleGroups[id]) {
      world.removeParticleGroup(id);
      continue;
    }
    world.m_particleGroups[id]->asleep = image.particleGroups[id]->asleep;
    world.m_particleGroups[id]->sleepCount = image.particleGroups[id]->sleepCount;
  }

  meshes.clear();
  meshes.m_convexMeshes.swap(image.convexMeshes);
  meshes.m_largeMeshes.swap(image.largeMeshes);
}

PfxInt32 pfxSaveWorldToBytes(const PfxWorld& world, std::vector<PfxUInt8>& bytes,
                             std::string* error) {
  constexpr const char* kFunction = "pfxSaveWorldToBytes";
  PfxSerializeError failure;
  PfxSerializeCapacity counts;
  PfxSerializeBuffer buffer;
  PfxWorldParam param;
  double time = 0;
  PfxSerializeContacts contacts;
  PfxSerializeAccess::describeWorld(world, counts, buffer, param, time, contacts);
  const PfxSerializeRemovals removals = PfxSerializeAccess::removals(world);
  std::vector<PfxUInt8> encoded;
  if (pfxEncodeSerialized(counts, buffer, encoded, failure, &PfxSerializeAccess::particleGroups(world), &removals) != PFX_OK) {
    return fail(kFunction, failure, error);
  }
  {
    PfxSerializeImage check;
    if (pfxDecodeSerialized(encoded, check, failure, nullptr, nullptr) != PFX_OK) {
      return fail(kFunction, failure, error);
    }
  }
  bytes.swap(encoded);
  return PFX_OK;
}

PfxInt32 pfxSaveWorld(const PfxWorld& world, FILE* file, std::string* error) {
  constexpr const char* kFunction = "pfxSaveWorld";
  if (!file) return failNull(kFunction, "the file", error);
  PfxSerializeError failure;
  std::vector<PfxUInt8> bytes;
  const PfxInt32 err = pfxSaveWorldToBytes(world, bytes, error);
  if (err != PFX_OK) return err;
  if (std::fwrite(bytes.data(), 1, bytes.size(), file) != bytes.size() || std::fflush(file) != 0) {
    failure.code = PFX_ERR_OUT_OF_BUFFER;
    failure.reason = "the stream refused the bytes";
    return fail(kFunction, failure, error);
  }
  return PFX_OK;
}

PfxInt32 pfxSaveWorld(const PfxWorld& world, const char* path, std::string* error) {
  FILE* file = path ? std::fopen(path, "wb") : nullptr;
  if (!file) return failOpen("pfxSaveWorld", path, "writing", error);
  const PfxInt32 err = pfxSaveWorld(world, file, error);
  const bool closed = std::fclose(file) == 0;
  if (err != PFX_OK) return err;
  if (!closed) return failOpen("pfxSaveWorld", path, "writing (closing failed)", error);
  return PFX_OK;
}

namespace {

bool rejectThreadCount(const PfxLoadWorldOptions& options, PfxSerializeError& failure) {
  if (options.keepSavedNumThreads || options.numThreads <= PFX_MAX_THREADS) return false;
  failure.code = PFX_ERR_OUT_OF_RANGE;
  failure.reason = "PfxLoadWorldOptions::numThreads is " + std::to_string(options.numThreads) +
                   ", more than PFX_MAX_THREADS";
  return true;
}

// Decodes a whole file's bytes and, only when every check passed, replaces the world.
PfxInt32 loadDecoded(const char* function, PfxWorld& world, const std::vector<PfxUInt8>& bytes,
                     PfxSerializedMeshes& meshes, std::string* error,
                     const PfxLoadWorldOptions& options) {
  PfxSerializeError failure;
  PfxSerializeImage image;
  if (pfxDecodeSerialized(bytes, image, failure, nullptr, nullptr) != PFX_OK) {
    return fail(function, failure, error);
  }
  PfxSerializeAccess::restoreWorld(world, image, options, meshes);
  return PFX_OK;
}

}  // namespace

PfxInt32 pfxLoadWorld(PfxWorld& world, FILE* file, PfxSerializedMeshes& meshes, std::string* error,
                      const PfxLoadWorldOptions& options) {
  constexpr const char* kFunction = "pfxLoadWorld";
  if (!file) return failNull(kFunction, "the file", error);
  PfxSerializeError failure;
  if (rejectThreadCount(options, failure)) return fail(kFunction, failure, error);
  std::vector<PfxUInt8> bytes;
  if (pfxReadSerializedBytes(file, bytes, failure) != PFX_OK)
    return fail(kFunction, failure, error);
  return loadDecoded(kFunction, world, bytes, meshes, error, options);
}

PfxInt32 pfxLoadWorldFromBytes(PfxWorld& world, const PfxUInt8* data, std::size_t size,
                               PfxSerializedMeshes& meshes, std::string* error,
                               const PfxLoadWorldOptions& options) {
  constexpr const char* kFunction = "pfxLoadWorldFromBytes";
  if (!data && size > 0) return failNull(kFunction, "the bytes", error);
  PfxSerializeError failure;
  if (rejectThreadCount(options, failure)) return fail(kFunction, failure, error);
  // Bytes past the length the header announces would be ignored; a short buffer is the
  // reader's to report, as for a file cut short.
  if (size >= kPfxSerializeHeaderBytes) {
    const PfxUInt64 bodyBytes = pfxLoadLittle<PfxUInt64>(data + 16);
    if (bodyBytes < size - kPfxSerializeHeaderBytes &&
        std::memcmp(data, kPfxSerializeMagic, sizeof(kPfxSerializeMagic)) == 0) {
      failure.code = PFX_ERR_OUT_OF_BUFFER;
      failure.tags = {"body"};
      failure.reason = std::to_string(size - kPfxSerializeHeaderBytes) +
                       " bytes follow the header, which announces " + std::to_string(bodyBytes);
      return fail(kFunction, failure, error);
    }
  }
  const std::vector<PfxUInt8> bytes(data, data + size);
  return loadDecoded(kFunction, world, bytes, meshes, error, options);
}

PfxInt32 pfxLoadWorld(PfxWorld& world, const char* path, PfxSerializedMeshes& meshes,
                      std::string* error, const PfxLoadWorldOptions& options) {
  FILE* file = path ? std::fopen(path, "rb") : nullptr;
  if (!file) return failOpen("pfxLoadWorld", path, "reading", error);
  const PfxInt32 err = pfxLoadWorld(world, file, meshes, error, options);
  std::fclose(file);
  return err;
}

}  // namespace pfx
