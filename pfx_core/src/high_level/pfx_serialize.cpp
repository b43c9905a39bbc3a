// The seed's entry points (pfxSerializeWrite, pfxSerializeRead) over the application's
// arrays, and the owner of the meshes a world load allocates.
#include "pfx/high_level/pfx_serialize.h"

#include "high_level/pfx_serialize_image.h"
#include "low_level/pfx_param_checks.h"

namespace pfx {

namespace {

// Hands the failure to the error callback and to pfxGetLastErrorDetail.
PfxInt32 report(const PfxSerializeCallbacks& callbacks, const char* function,
                const PfxSerializeError& error) {
  if (callbacks.error) {
    std::vector<const char*> tags;
    for (const std::string& tag : error.tags) tags.push_back(tag.c_str());
    callbacks.error(error.code, tags.data(), static_cast<PfxUInt32>(tags.size()),
                    callbacks.userData);
  }
  return pfxRejectParam(error.code, "%s: %s", function, error.describe().c_str());
}

PfxSerializeError argumentError(PfxInt32 code, const std::string& reason) {
  PfxSerializeError error;
  error.code = code;
  error.reason = reason;
  return error;
}

// What both entry points do first: check the file and the init callback, then let the
// callback name the arrays and their sizes.
PfxInt32 initializeSerializer(FILE* file, const PfxSerializeCallbacks& callbacks,
                              const char* function, PfxSerializeCapacity& capacity,
                              PfxSerializeBuffer& buffer) {
  if (!file || !callbacks.init) {
    return report(callbacks, function,
                  argumentError(PFX_ERR_NULL_POINTER,
                                file ? "the init callback is null" : "the file is null"));
  }
  if (!callbacks.init(capacity, buffer, callbacks.userData)) {
    return report(callbacks, function,
                  argumentError(PFX_ERR_OUT_OF_BUFFER, "the init callback returned false"));
  }
  return PFX_OK;
}

// The first count of `needed` that `capacity` falls short of, or null.
const char* shortfall(const PfxSerializeCapacity& capacity, const PfxSerializeCapacity& needed,
                      PfxUInt32& have, PfxUInt32& need) {
  const struct {
    PfxUInt32 have, need;
    const char* name;
  } counts[] = {
      {capacity.numRigidBodies, needed.numRigidBodies, "numRigidBodies"},
      {capacity.numShapes, needed.numShapes, "numShapes"},
      {capacity.numJoints, needed.numJoints, "numJoints"},
      {capacity.numJointCouplings, needed.numJointCouplings, "numJointCouplings"},
      {capacity.numContactPairs, needed.numContactPairs, "numContactPairs"},
      {capacity.numSleepingPairs, needed.numSleepingPairs, "numSleepingPairs"},
      {capacity.numContactManifolds, needed.numContactManifolds, "numContactManifolds"},
      {capacity.numFreeManifolds, needed.numFreeManifolds, "numFreeManifolds"},
      {capacity.numExcludedPairs, needed.numExcludedPairs, "numExcludedPairs"},
      {capacity.numConvexMeshes, needed.numConvexMeshes, "numConvexMeshes"},
      {capacity.numLargeMeshes, needed.numLargeMeshes, "numLargeMeshes"},
  };
  for (const auto& c : counts) {
    if (c.have < c.need) {
      have = c.have;
      need = c.need;
      return c.name;
    }
  }
  return nullptr;
}

// The array of `buffer` that is null while `needed` has elements for it, or null.
const char* missingArray(const PfxSerializeBuffer& b, const PfxSerializeCapacity& n) {
  const struct {
    const void* pointer;
    PfxUInt32 count;
    const char* name;
  } arrays[] = {
      {b.rigidStates, n.numRigidBodies, "rigidStates"},
      {b.rigidBodies, n.numRigidBodies, "rigidBodies"},
      {b.collidables, n.numRigidBodies, "collidables"},
      {b.forces, n.numRigidBodies, "forces"},
      {b.torques, n.numRigidBodies, "torques"},
      {b.shapes, n.numShapes, "shapes"},
      {b.shapeIds, n.numShapes, "shapeIds"},
      {b.joints, n.numJoints, "joints"},
      {b.jointCouplings, n.numJointCouplings, "jointCouplings"},
      {b.contactPairs, n.numContactPairs, "contactPairs"},
      {b.sleepingPairs, n.numSleepingPairs, "sleepingPairs"},
      {b.contactManifolds, n.numContactManifolds, "contactManifolds"},
      {b.freeManifolds, n.numFreeManifolds, "freeManifolds"},
      {b.excludedPairKeys, n.numExcludedPairs, "excludedPairKeys"},
      {b.convexMeshes, n.numConvexMeshes, "convexMeshes"},
      {b.largeMeshes, n.numLargeMeshes, "largeMeshes"},
  };
  for (const auto& a : arrays) {
    if (!a.pointer && a.count > 0) return a.name;
  }
  return nullptr;
}

// Copies the checked image into the application's arrays and gives it the meshes.
void store(PfxSerializeImage& image, const PfxSerializeBuffer& b) {
  *b.worldParam = image.param;
  *b.simulatedTime = image.simulatedTime;
  std::copy(image.states.begin(), image.states.end(), b.rigidStates);
  std::copy(image.bodies.begin(), image.bodies.end(), b.rigidBodies);
  std::copy(image.forces.begin(), image.forces.end(), b.forces);
  std::copy(image.torques.begin(), image.torques.end(), b.torques);
  PfxUInt32 nextShape = 0;
  for (PfxUInt32 id = 0; id < image.numBodies(); ++id) {
    const PfxUInt32 first = image.firstShape[id];
    const PfxUInt32 count = image.firstShape[id + 1] - first;
    PfxCollidable& collidable = b.collidables[id];
    if (count == 1) {
      collidable.reset();
    } else {
      for (PfxUInt32 i = 0; i < count; ++i) b.shapeIds[nextShape + i] = static_cast<PfxUInt16>(i);
      collidable.reset(b.shapes + nextShape, b.shapeIds + nextShape, count);
      nextShape += count;
    }
    for (PfxUInt32 i = 0; i < count; ++i) collidable.addShape(image.shapes[first + i]);
    collidable.finish();
  }
  std::copy(image.joints.begin(), image.joints.end(), b.joints);
  std::copy(image.jointCouplings.begin(), image.jointCouplings.end(), b.jointCouplings);
  std::copy(image.pairs.begin(), image.pairs.end(), b.contactPairs);
  std::copy(image.sleepingPairs.begin(), image.sleepingPairs.end(), b.sleepingPairs);
  std::copy(image.manifolds.begin(), image.manifolds.end(), b.contactManifolds);
  std::copy(image.freeManifolds.begin(), image.freeManifolds.end(), b.freeManifolds);
  std::copy(image.excludedPairKeys.begin(), image.excludedPairKeys.end(), b.excludedPairKeys);
  std::copy(image.convexMeshes.begin(), image.convexMeshes.end(), b.convexMeshes);
  std::copy(image.largeMeshes.begin(), image.largeMeshes.end(), b.largeMeshes);
  image.convexMeshes.clear();
  image.largeMeshes.clear();
}

}  // namespace

PfxInt32 pfxSerializeWrite(FILE* file, const PfxSerializeCallbacks& callbacks) {
  constexpr const char* kFunction = "pfxSerializeWrite";
  PfxSerializeCapacity counts;
  PfxSerializeBuffer buffer;
  if (const PfxInt32 code = initializeSerializer(file, callbacks, kFunction, counts, buffer);
      code != PFX_OK) {
    return code;
  }
  PfxSerializeError error;
  std::vector<PfxUInt8> bytes;
  if (pfxEncodeSerialized(counts, buffer, bytes, error) != PFX_OK) {
    return report(callbacks, kFunction, error);
  }
  // What cannot be read back is not written: the reader's checks run on the bytes first.
  {
    PfxSerializeImage check;
    if (pfxDecodeSerialized(bytes, check, error, nullptr, nullptr) != PFX_OK) {
      return report(callbacks, kFunction, error);
    }
  }
  if (std::fwrite(bytes.data(), 1, bytes.size(), file) != bytes.size() || std::fflush(file) != 0) {
    return report(callbacks, kFunction,
                  argumentError(PFX_ERR_OUT_OF_BUFFER, "the stream refused the bytes"));
  }
  if (callbacks.term) callbacks.term(counts, buffer, callbacks.userData);
  return PFX_OK;
}

PfxInt32 pfxSerializeRead(FILE* file, const PfxSerializeCallbacks& callbacks) {
  constexpr const char* kFunction = "pfxSerializeRead";
  PfxSerializeCapacity capacity;
  PfxSerializeBuffer buffer;
  if (const PfxInt32 code = initializeSerializer(file, callbacks, kFunction, capacity, buffer);
      code != PFX_OK) {
    return code;
  }
  if (!buffer.worldParam || !buffer.simulatedTime) {
    return report(callbacks, kFunction,
                  argumentError(PFX_ERR_NULL_POINTER,
                                "PfxSerializeBuffer::worldParam or simulatedTime is null"));
  }
  PfxSerializeError error;
  std::vector<PfxUInt8> bytes;
  if (pfxReadSerializedBytes(file, bytes, error) != PFX_OK) {
    return report(callbacks, kFunction, error);
  }
  PfxSerializeImage image;
  if (pfxDecodeSerialized(bytes, image, error, callbacks.update, callbacks.userData) != PFX_OK) {
    return report(callbacks, kFunction, error);
  }
  if (!image.particleGroups.empty()) {
    error.code = PFX_ERR_OUT_OF_BUFFER;
    error.tags = {"particle groups"};
    error.reason = "the file holds a world's particle groups, which PfxSerializeBuffer has no "
                   "place for: load it with pfxLoadWorld";
    return report(callbacks, kFunction, error);
  }
  if (!image.removals.empty()) {
    error.code = PFX_ERR_OUT_OF_BUFFER;
    error.tags = {"removed slots"};
    error.reason = "the file holds a world's removed bodies or joints, which PfxSerializeBuffer "
                   "has no place for: load it with pfxLoadWorld";
    return report(callbacks, kFunction, error);
  }
  const PfxSerializeCapacity needed = image.capacity();
  PfxUInt32 have = 0, need = 0;
  if (const char* name = shortfall(capacity, needed, have, need)) {
    const bool resized = callbacks.resize &&
                         callbacks.resize(capacity, buffer, needed, callbacks.userData) &&
                         !shortfall(capacity, needed, have, need);
    if (!resized) {
      error.code = PFX_ERR_OUT_OF_BUFFER;
      error.tags = {"buffer", name};
      error.reason = "holds " + std::to_string(have) + ", the file " + std::to_string(need);
      return report(callbacks, kFunction, error);
    }
  }
  if (const char* name = missingArray(buffer, needed)) {
    return report(callbacks, kFunction,
                  argumentError(PFX_ERR_NULL_POINTER,
                                std::string("PfxSerializeBuffer::") + name + " is null"));
  }
  store(image, buffer);
  if (callbacks.term) callbacks.term(needed, buffer, callbacks.userData);
  return PFX_OK;
}

PfxSerializedMeshes::PfxSerializedMeshes(PfxSerializedMeshes&& other) noexcept
    : m_convexMeshes(std::move(other.m_convexMeshes)),
      m_largeMeshes(std::move(other.m_largeMeshes)) {
  other.m_convexMeshes.clear();
  other.m_largeMeshes.clear();
}

PfxSerializedMeshes& PfxSerializedMeshes::operator=(PfxSerializedMeshes&& other) noexcept {
  if (this != &other) {
    clear();
    m_convexMeshes.swap(other.m_convexMeshes);
    m_largeMeshes.swap(other.m_largeMeshes);
  }
  return *this;
}

void PfxSerializedMeshes::clear() {
  for (PfxConvexMesh* mesh : m_convexMeshes) pfxDeleteConvexMesh(mesh);
  for (PfxLargeTriMesh* mesh : m_largeMeshes) pfxDeleteLargeTriMesh(mesh);
  m_convexMeshes.clear();
  m_largeMeshes.clear();
}

}  // namespace pfx
