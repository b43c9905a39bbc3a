// The writer: the application's arrays to bytes, field by field in the order the reader
// takes them (README.md, "Serialization"), never as raw structs, so that the bytes do not
// depend on the compiler's layout.
#include <algorithm>
#include <cstring>
#include <unordered_map>

#include "high_level/pfx_serialize_image.h"

namespace pfx {

namespace {

class Encoder {
 public:
  Encoder(const PfxSerializeCapacity& counts, const PfxSerializeBuffer& buffer,
          PfxByteWriter& writer, PfxSerializeError& error)
      : m_counts(counts), m_buffer(buffer), w(writer), m_error(error) {}

  bool checkBuffer();
  bool collectMeshes();
  void param();
  void convexMeshes();
  void largeMeshes();
  void bodies();
  void joints();
  void couplings();
  void exclusions();
  bool contacts();

 private:
  bool fail(PfxInt32 code, std::vector<std::string> tags, const std::string& reason) {
    m_error.code = code;
    m_error.tags = std::move(tags);
    m_error.reason = reason;
    return false;
  }
  void shape(const PfxShape& shape);
  void jointConstraint(const PfxJointConstraint& c);
  void manifold(const PfxContactManifold& manifold);
  void pairs(const PfxBroadphasePair* pairs, PfxUInt32 count);

  const PfxSerializeCapacity& m_counts;
  const PfxSerializeBuffer& m_buffer;
  PfxByteWriter& w;
  PfxSerializeError& m_error;
  // Each mesh once, numbered in the order the bodies first name it.
  std::vector<const PfxConvexMesh*> m_convexMeshes;
  std::vector<const PfxLargeTriMesh*> m_largeMeshes;
  std::unordered_map<const void*, PfxUInt32> m_meshIndex;
};

bool Encoder::checkBuffer() {
  const PfxSerializeBuffer& b = m_buffer;
  const PfxSerializeCapacity& c = m_counts;
  const struct {
    const void* pointer;
    PfxUInt32 count;
    const char* name;
  } arrays[] = {
      {b.worldParam, 1, "worldParam"},
      {b.simulatedTime, 1, "simulatedTime"},
      {b.rigidStates, c.numRigidBodies, "rigidStates"},
      {b.rigidBodies, c.numRigidBodies, "rigidBodies"},
      {b.collidables, c.numRigidBodies, "collidables"},
      {b.forces, c.numRigidBodies, "forces"},
      {b.torques, c.numRigidBodies, "torques"},
      {b.joints, c.numJoints, "joints"},
      {b.jointCouplings, c.numJointCouplings, "jointCouplings"},
      {b.contactPairs, c.numContactPairs, "contactPairs"},
      {b.sleepingPairs, c.numSleepingPairs, "sleepingPairs"},
      {b.contactManifolds, c.numContactManifolds, "contactManifolds"},
      {b.freeManifolds, c.numFreeManifolds, "freeManifolds"},
      {b.excludedPairKeys, c.numExcludedPairs, "excludedPairKeys"},
  };
  for (const auto& array : arrays) {
    if (!array.pointer && array.count > 0) {
      return fail(PFX_ERR_NULL_POINTER, {},
                  std::string("PfxSerializeBuffer::") + array.name + " is null, but " +
                      std::to_string(array.count) + " are to be written");
    }
  }
  return true;
}

bool Encoder::collectMeshes() {
  for (PfxUInt32 id = 0; id < m_counts.numRigidBodies; ++id) {
    const PfxCollidable& collidable = m_buffer.collidables[id];
    for (PfxUInt32 i = 0; i < collidable.getNumShapes(); ++i) {
      const PfxShape& shape = collidable.getShape(i);
      const void* mesh = nullptr;
      if (shape.getType() == kPfxShapeConvexMesh) mesh = shape.getConvexMesh();
      if (shape.getType() == kPfxShapeLargeTriMesh) mesh = shape.getLargeTriMesh();
      if (shape.getType() < kPfxShapeConvexMesh || m_meshIndex.count(mesh)) continue;
      if (!mesh ||
          (shape.getType() == kPfxShapeLargeTriMesh && !shape.getLargeTriMesh()->m_block)) {
        return fail(PFX_ERR_NULL_POINTER,
                    {"bodies", "body " + std::to_string(id), "shape " + std::to_string(i)},
                    "names no mesh, or a mesh without its arrays");
      }
      if (shape.getType() == kPfxShapeConvexMesh) {
        m_meshIndex[mesh] = static_cast<PfxUInt32>(m_convexMeshes.size());
        m_convexMeshes.push_back(shape.getConvexMesh());
      } else {
        m_meshIndex[mesh] = static_cast<PfxUInt32>(m_largeMeshes.size());
        m_largeMeshes.push_back(shape.getLargeTriMesh());
      }
    }
  }
  return true;
}

void Encoder::param() {
  const PfxWorldParam& p = *m_buffer.worldParam;
  w.vec3(p.worldCenter);
  w.vec3(p.worldExtent);
  w.vec3(p.gravity);
  w.real(p.timeStep);
  w.u32(p.subStep);
  w.u32(p.iteration);
  w.u8(p.pipeline);
  w.real(p.separateBias);
  w.real(p.contactSlop);
  w.real(p.contactMargin);
  w.real(p.restitutionThreshold);
  w.u8(p.measureConservation ? 1 : 0);
  w.u32(p.outOfWorldBehavior);
  w.u8(p.enableSleep ? 1 : 0);
  w.real(p.sleepLinearVelocity);
  w.real(p.sleepAngularVelocity);
  w.real(p.sleepTime);
  w.u32(p.numThreads);
  w.f64(*m_buffer.simulatedTime);
  // Version 2.
  w.u8(p.enableShockPropagation ? 1 : 0);
  // Version 3.
  w.u8(p.measureStages ? 1 : 0);
}

void Encoder::convexMeshes() {
  w.u32(static_cast<PfxUInt32>(m_convexMeshes.size()));
  for (const PfxConvexMesh* mesh : m_convexMeshes) {
    w.u8(mesh->m_numVerts);
    w.u8(mesh->m_numFacets);
    w.u8(mesh->m_numEdges);
    w.u8(mesh->m_numFaces);
    for (PfxUInt32 i = 0; i < mesh->m_numVerts; ++i) w.vec3(mesh->m_verts[i]);
    for (PfxUInt32 i = 0; i < mesh->m_numFacets; ++i) {
      for (PfxUInt8 id : mesh->m_facetVertIds[i]) w.u8(id);
    }
    for (PfxUInt32 i = 0; i < mesh->m_numEdges; ++i) {
      for (PfxUInt8 id : mesh->m_edgeVertIds[i]) w.u8(id);
    }
    // Only the corners the faces use; the rest of the array is never read.
    PfxUInt32 numFaceVertIds = 0;
    for (PfxUInt32 i = 0; i < mesh->m_numFaces; ++i) {
      numFaceVertIds =
          std::max<PfxUInt32>(numFaceVertIds, mesh->m_faceFirstVert[i] + mesh->m_faceNumVerts[i]);
    }
    w.u8(static_cast<PfxUInt8>(numFaceVertIds));
    for (PfxUInt32 i = 0; i < mesh->m_numFaces; ++i) {
      w.vec3(mesh->m_faceNormals[i]);
      w.real(mesh->m_facePlaneDist[i]);
      w.u8(mesh->m_faceFirstVert[i]);
      w.u8(mesh->m_faceNumVerts[i]);
    }
    for (PfxUInt32 i = 0; i < numFaceVertIds; ++i) w.u8(mesh->m_faceVertIds[i]);
    w.vec3(mesh->m_aabbCenter);
    w.vec3(mesh->m_aabbHalf);
  }
}

// The arrays as stored; the node bounds and the mesh's bounds are left out, as the reader
// recomputes them from the vertices.
void Encoder::largeMeshes() {
  w.u32(static_cast<PfxUInt32>(m_largeMeshes.size()));
  for (const PfxLargeTriMesh* mesh : m_largeMeshes) {
    const bool quantized = mesh->m_quantizedVertices != nullptr;
    const bool cornerOffsets = mesh->m_triangleOffsets != nullptr;
    const bool sourceOffsets = mesh->m_triangleSourceOffsets != nullptr;
    w.u32(mesh->m_flags);
    w.u8(PfxUInt8((quantized ? 1 : 0) | (cornerOffsets ? 2 : 0) | (sourceOffsets ? 4 : 0)));
    w.u32(mesh->m_numVertices);
    w.u32(mesh->m_numTriangles);
    w.u32(mesh->m_numSourceTriangles);
    w.u32(mesh->m_numIslands);
    w.u32(mesh->m_numNodes);
    w.real(mesh->m_thickness);
    w.vec3(mesh->m_quantOrigin);
    w.vec3(mesh->m_quantStep);
    for (PfxUInt64 i = 0; i < 3ull * mesh->m_numVertices; ++i) {
      if (quantized) {
        w.u16(mesh->m_quantizedVertices[i]);
      } else {
        w.real(mesh->m_vertices[i]);
      }
    }
    for (PfxUInt64 i = 0; i < 3ull * mesh->m_numTriangles; ++i) {
      if (cornerOffsets) {
        w.u16(mesh->m_triangleOffsets[i]);
      } else {
        w.u32(mesh->m_triangleVertices[i]);
      }
    }
    for (PfxUInt32 t = 0; t < mesh->m_numTriangles; ++t) {
      if (sourceOffsets) {
        w.u16(mesh->m_triangleSourceOffsets[t]);
      } else {
        w.u32(mesh->m_triangleSourceIds[t]);
      }
    }
    for (PfxUInt32 t = 0; t < mesh->m_numTriangles; ++t) w.u8(mesh->m_edgeFlags[t]);
    for (PfxUInt32 i = 0; i < mesh->m_numIslands; ++i) {
      const PfxLargeMeshIsland& island = mesh->m_islands[i];
      w.u32(island.m_firstTriangle);
      w.u32(island.m_baseVertex);
      w.u32(island.m_baseSource);
      w.u32(island.m_numTriangles);
    }
    for (PfxUInt32 i = 0; i < mesh->m_numNodes; ++i) {
      const PfxUInt32* links =
          quantized ? mesh->m_quantizedNodes[i].m_links : mesh->m_nodes[i].m_links;
      for (PfxUInt32 c = 0; c < PFX_LARGE_MESH_NODE_WIDTH; ++c) w.u32(links[c]);
    }
  }
}

void Encoder::shape(const PfxShape& shape) {
  w.u8(shape.getType());
  w.vec3(shape.getOffsetPosition());
  w.quat(shape.getOffsetOrientation());
  switch (shape.getType()) {
    case kPfxShapeSphere:
      w.real(shape.getSphere().m_radius);
      break;
    case kPfxShapeBox:
      w.vec3(shape.getBox().m_half);
      break;
    case kPfxShapeCapsule:
      w.real(shape.getCapsule().m_halfLen);
      w.real(shape.getCapsule().m_radius);
      break;
    case kPfxShapeCylinder:
      w.real(shape.getCylinder().m_halfLen);
      w.real(shape.getCylinder().m_radius);
      break;
    case kPfxShapeConvexMesh:
      w.u32(m_meshIndex.at(shape.getConvexMesh()));
      break;
    default:
      w.u32(m_meshIndex.at(shape.getLargeTriMesh()));
      break;
  }
}

void Encoder::bodies() {
  w.u32(m_counts.numRigidBodies);
  for (PfxUInt32 id = 0; id < m_counts.numRigidBodies; ++id) {
    const PfxRigidState& s = m_buffer.rigidStates[id];
    w.vec3(s.getPosition());
    w.quat(s.getOrientation());
    w.vec3(s.getLinearVelocity());
    w.vec3(s.getAngularVelocity());
    // Version 2.
    w.quat(s.getOrientationCarry());
    w.vec3(s.getAngularVelocityCarry());
    w.u32(s.getRigidBodyId());
    w.u32(s.getContactFilterSelf());
    w.u32(s.getContactFilterTarget());
    w.u16(s.getSleepCount());
    w.u8(s.getMotionType());
    w.u8(s.isAsleep() ? 1 : 0);
    const PfxRigidBody& b = m_buffer.rigidBodies[id];
    w.real(b.getMass());
    w.mat3(b.getInertia());
    w.real(b.getFriction());
    w.real(b.getRestitution());
    w.vec3(m_buffer.forces[id]);
    w.vec3(m_buffer.torques[id]);
    const PfxCollidable& collidable = m_buffer.collidables[id];
    w.u8(static_cast<PfxUInt8>(collidable.getNumShapes()));
    for (PfxUInt32 i = 0; i < collidable.getNumShapes(); ++i) shape(collidable.getShape(i));
  }
}

void Encoder::jointConstraint(const PfxJointConstraint& c) {
  w.u8(c.m_lock);
  w.u8(c.m_drive);
  w.u8(c.m_rowType);
  w.u8(c.m_driveRowUsed);
  w.real(c.m_movableLowerLimit);
  w.real(c.m_movableUpperLimit);
  w.real(c.m_bias);
  w.real(c.m_weight);
  w.real(c.m_damping);
  w.real(c.m_friction);
  w.real(c.m_driveTarget);
  w.real(c.m_driveMaxForce);
  w.row(c.m_constraintRow);
  w.row(c.m_driveRow);
  w.real(c.m_pushRhs);
  w.real(c.m_pushImpulse);
  w.real(c.m_position);
  w.real(c.m_treeResponse[0]);
  w.real(c.m_treeResponse[1]);
}

void Encoder::joints() {
  w.u32(m_counts.numJoints);
  for (PfxUInt32 j = 0; j < m_counts.numJoints; ++j) {
    const PfxJoint& joint = m_buffer.joints[j];
    for (const PfxJointConstraint& c : joint.m_constraints) jointConstraint(c);
    w.mat3(joint.m_frameA);
    w.mat3(joint.m_frameB);
    w.vec3(joint.m_anchorA);
    w.vec3(joint.m_anchorB);
    w.u32(joint.m_rigidBodyIdA);
    w.u32(joint.m_rigidBodyIdB);
    w.u8(joint.m_active);
    w.u8(joint.m_type);
    w.u8(joint.m_rotation);
    w.vec3(joint.m_armA);
    w.vec3(joint.m_armB);
    for (const PfxVector3& axis : joint.m_axes) w.vec3(axis);
  }
}

void Encoder::couplings() {
  w.u32(m_counts.numJointCouplings);
  for (PfxUInt32 k = 0; k < m_counts.numJointCouplings; ++k) {
    const PfxJointCoupling& c = m_buffer.jointCouplings[k];
    w.u32(c.m_leaderJointId);
    w.u32(c.m_followerJointId);
    w.u8(c.m_leaderAxis);
    w.u8(c.m_followerAxis);
    w.u8(c.m_active);
    w.u8(c.m_numBodies);
    w.real(c.m_multiplier);
    w.real(c.m_offset);
    w.real(c.m_bias);
    w.real(c.m_maxImpulseForce);
    w.real(c.m_leaderPosition);
    w.real(c.m_followerPosition);
    w.row(c.m_row);
    // Entries past m_numBodies are never read, and may never have been set.
    for (PfxUInt32 b = 0; b < std::min<PfxUInt32>(c.m_numBodies, PFX_JOINT_COUPLING_MAX_BODIES);
         ++b) {
      w.vec3(c.m_bodies[b].m_linear);
      w.vec3(c.m_bodies[b].m_angular);
      w.u32(c.m_bodies[b].m_rigidBodyId);
    }
    w.real(c.m_pushRhs);
    w.real(c.m_pushImpulse);
    w.real(c.m_error);
  }
}

void Encoder::exclusions() {
  w.u32(m_counts.numExcludedPairs);
  for (PfxUInt32 i = 0; i < m_counts.numExcludedPairs; ++i) w.u64(m_buffer.excludedPairKeys[i]);
}

void Encoder::manifold(const PfxContactManifold& manifold) {
  const PfxUInt32 numContacts = manifold.getNumContacts();
  w.u32(manifold.getRigidBodyIdA());
  w.u32(manifold.getRigidBodyIdB());
  w.u8(static_cast<PfxUInt8>(numContacts));
  w.real(manifold.getCompositeFriction());
  w.real(manifold.getCompositeRestitution());
  // Couplings and points past numContacts are stale: never read, not written.
  for (PfxUInt32 i = 0; i < numContacts; ++i) {
    for (PfxUInt32 j = 0; j < numContacts; ++j) w.real(manifold.getNormalCoupling(i, j));
  }
  for (PfxUInt32 i = 0; i < numContacts; ++i) {
    const PfxContactPoint& p = manifold.getContactPoint(i);
    for (const PfxConstraintRow& row : p.m_constraintRow) w.row(row);
    w.vec3(p.m_localPointA);
    w.vec3(p.m_localPointB);
    w.vec3(p.m_armA);
    w.vec3(p.m_armB);
    w.real(p.m_distance);
    w.real(p.m_approachVelocity);
    w.real(p.m_maxImpulse);
    w.real(p.m_pushRhs);
    w.real(p.m_pushImpulse);
    w.u32(p.m_duration);
    w.u8(p.m_shapeIdA);
    w.u8(p.m_shapeIdB);
    w.u32(p.m_triangleIndex);
    for (PfxFloat b : p.m_barycentric) w.real(b);
  }
}

void Encoder::pairs(const PfxBroadphasePair* pairs, PfxUInt32 count) {
  w.u32(count);
  for (PfxUInt32 i = 0; i < count; ++i) {
    w.u64(pairs[i].key);
    w.u32(pairs[i].data[0]);
    w.u32(pairs[i].data[1]);
  }
}

bool Encoder::contacts() {
  const PfxUInt32 numManifolds = m_counts.numContactManifolds;
  std::vector<bool> isFree(numManifolds, false);
  for (PfxUInt32 i = 0; i < m_counts.numFreeManifolds; ++i) {
    const PfxUInt32 id = m_buffer.freeManifolds[i];
    if (id >= numManifolds) {
      return fail(PFX_ERR_OUT_OF_RANGE, {"contacts", "freeManifolds"},
                  "slot " + std::to_string(id) + " is not below the " +
                      std::to_string(numManifolds) + " manifolds");
    }
    isFree[id] = true;
  }
  w.u32(numManifolds);
  w.u32(m_counts.numFreeManifolds);
  for (PfxUInt32 i = 0; i < m_counts.numFreeManifolds; ++i) w.u32(m_buffer.freeManifolds[i]);
  for (PfxUInt32 i = 0; i < numManifolds; ++i) {
    if (isFree[i]) continue;
    if (m_buffer.contactManifolds[i].getNumContacts() > PFX_NUM_CONTACTS_PER_MANIFOLD) {
      return fail(PFX_ERR_OUT_OF_RANGE, {"contacts", "manifold " + std::to_string(i)},
                  "holds more than 4 points");
    }
    manifold(m_buffer.contactManifolds[i]);
  }
  pairs(m_buffer.contactPairs, m_counts.numContactPairs);
  pairs(m_buffer.sleepingPairs, m_counts.numSleepingPairs);
  return true;
}

}  // namespace

PfxInt32 pfxEncodeSerialized(const PfxSerializeCapacity& counts, const PfxSerializeBuffer& buffer,
                             std::vector<PfxUInt8>& bytes, PfxSerializeError& error,
                             const std::vector<std::unique_ptr<PfxParticleGroup>>* particleGroups,
                             const PfxSerializeRemovals* removals) {
  PfxByteWriter w;
  Encoder encoder(counts, buffer, w, error);
  if (!encoder.checkBuffer() || !encoder.collectMeshes()) return error.code;
  for (char c : kPfxSerializeMagic) w.u8(static_cast<PfxUInt8>(c));
  w.u32(PFX_SERIALIZE_VERSION);
  w.u8(sizeof(PfxFloat));
  for (int i = 0; i < 3; ++i) w.u8(0);
  const std::size_t lengthAt = w.bytes().size();
  w.u64(0);
  w.u64(0);

  const auto section = [&](const char* tag, auto&& write) {
    const std::size_t start = w.beginSection(tag);
    write();
    w.endSection(start);
  };
  section("PARM", [&] { encoder.param(); });
  section("CMSH", [&] { encoder.convexMeshes(); });
  section("LMSH", [&] { encoder.largeMeshes(); });
  section("BODY", [&] { encoder.bodies(); });
  section("JOIN", [&] { encoder.joints(); });
  section("CPLG", [&] { encoder.couplings(); });
  section("EXCL", [&] { encoder.exclusions(); });
  bool contactsOk = true;
  section("CONT", [&] { contactsOk = encoder.contacts(); });
  if (!contactsOk) return error.code;
  if (removals && !removals->empty()) {
    section("GONE", [&] { pfxEncodeRemovals(w, *removals); });
  }
  if (particleGroups && !particleGroups->empty()) {
    section("PART", [&] { pfxEncodeParticleGroups(w, *particleGroups); });
  }

  std::vector<PfxUInt8>& out = w.bytes();
  const std::size_t bodyBytes = out.size() - kPfxSerializeHeaderBytes;
  w.patchU64(lengthAt, bodyBytes);
  w.patchU64(lengthAt + 8, pfxSerializeChecksum(out.data() + kPfxSerializeHeaderBytes, bodyBytes));
  bytes.swap(out);
  return PFX_OK;
}

PfxInt32 pfxReadSerializedBytes(FILE* file, std::vector<PfxUInt8>& bytes,
                                PfxSerializeError& error) {
  const auto fail = [&](const char* tag, const std::string& reason) {
    error.code = PFX_ERR_OUT_OF_BUFFER;
    error.tags = {tag};
    error.reason = reason;
    return error.code;
  };
  bytes.resize(kPfxSerializeHeaderBytes);
  const std::size_t headerRead = std::fread(bytes.data(), 1, kPfxSerializeHeaderBytes, file);
  if (headerRead != kPfxSerializeHeaderBytes) {
    return fail("header", "the file ends after " + std::to_string(headerRead) + " of its " +
                              std::to_string(kPfxSerializeHeaderBytes) + " bytes");
  }
  // A file of something else is said to be one before its length is believed.
  if (std::memcmp(bytes.data(), kPfxSerializeMagic, sizeof(kPfxSerializeMagic)) != 0) {
    error.code = PFX_ERR_INVALID_FLAG;
    error.tags = {"header", "magic"};
    error.reason = "this is not a pfx world file";
    return error.code;
  }
  const PfxUInt64 bodyBytes = pfxLoadLittle<PfxUInt64>(bytes.data() + 16);
  // Through a block on the stack, so that memory follows the bytes actually read, not the
  // length the header claims.
  PfxUInt8 block[16384];
  PfxUInt64 done = 0;
  while (done < bodyBytes) {
    const std::size_t want =
        static_cast<std::size_t>(std::min<PfxUInt64>(sizeof(block), bodyBytes - done));
    const std::size_t got = std::fread(block, 1, want, file);
    bytes.insert(bytes.end(), block, block + got);
    done += got;
    if (got != want) {
      return fail("body", "the file ends after " + std::to_string(done) + " of the " +
                              std::to_string(bodyBytes) + " bytes its header announces");
    }
  }
  return PFX_OK;
}

}  // namespace pfx
