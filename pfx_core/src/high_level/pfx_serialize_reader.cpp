// The reader: bytes to a checked PfxSerializeImage. Every count is checked against the
// bytes left before anything is allocated for it, every index against the array it
// indexes, and every value against what PfxWorld itself would accept, so that a file cannot
// make a later step read outside an array or start from NaN.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <iterator>
#include <sstream>

#include "base_level/collision/pfx_large_tri_mesh_access.h"
#include "high_level/pfx_serialize_image.h"

namespace pfx {

namespace {

// Smallest encoding of each element, for the count checks (a shape without its size, a
// manifold without its points, ...).
constexpr std::size_t kMinShapeBytes = 1 + 7 * 4;
constexpr std::size_t kMinBodyBytes = (13 * 4 + 16) + 18 * 4 + 1 + kMinShapeBytes;
constexpr std::size_t kMinJointBytes = 200;
constexpr std::size_t kMinCouplingBytes = 12 + 17 * 4;
constexpr std::size_t kMinManifoldBytes = 9 + 2 * 4;
constexpr std::size_t kMinConvexMeshBytes = 4 + 1 + 6 * 4;
constexpr std::size_t kMinLargeMeshBytes = 25 + 7 * 4;
constexpr std::size_t kPairBytes = 16;

std::string at(const char* what, std::size_t index) {
  return std::string(what) + " " + std::to_string(index);
}

class Parser {
 public:
  Parser(PfxByteReader& reader, PfxSerializeImage& image, PfxUInt32 version)
      : r(reader), m_image(image), m_version(version) {}

  bool header(std::size_t& realBytes);
  bool param();
  bool convexMeshes();
  bool largeMeshes();
  bool bodies();
  bool joints();
  bool couplings();
  bool exclusions();
  bool contacts();

 private:
  bool convexMesh(PfxConvexMesh& mesh);
  bool largeMesh(PfxLargeTriMesh& mesh);
  bool largeMeshLinks(PfxLargeTriMesh& mesh);
  bool shape(PfxShape& shape);
  bool jointConstraint(PfxJointConstraint& c);
  bool manifold(PfxContactManifold& manifold);
  bool contactPoint(PfxContactPoint& point, PfxUInt32 idA, PfxUInt32 idB);
  bool pairList(const char* name, std::vector<PfxBroadphasePair>& pairs,
                std::vector<PfxUInt8>& manifoldUse);
  const PfxShape& bodyShape(PfxUInt32 body, PfxUInt32 i) const {
    return m_image.shapes[m_image.firstShape[body] + i];
  }
  PfxUInt32 numShapes(PfxUInt32 body) const {
    return m_image.firstShape[body + 1] - m_image.firstShape[body];
  }

  PfxByteReader& r;
  PfxSerializeImage& m_image;
  // The file's format version: what a later version added is read only from its files.
  PfxUInt32 m_version;
};

bool Parser::param() {
  PfxWorldParam& p = m_image.param;
  p.worldCenter = r.vec3("worldCenter");
  p.worldExtent = r.vec3("worldExtent");
  p.gravity = r.vec3("gravity");
  p.timeStep = r.real("timeStep");
  p.subStep = r.u32("subStep");
  p.iteration = r.u32("iteration");
  p.pipeline = static_cast<PfxPipelineType>(r.u8("pipeline"));
  p.separateBias = r.real("separateBias");
  p.contactSlop = r.real("contactSlop");
  p.contactMargin = r.real("contactMargin");
  p.restitutionThreshold = r.real("restitutionThreshold");
  p.measureConservation = r.u8("measureConservation") != 0;
  p.outOfWorldBehavior = r.u32("outOfWorldBehavior");
  p.enableSleep = r.u8("enableSleep") != 0;
  p.sleepLinearVelocity = r.real("sleepLinearVelocity");
  p.sleepAngularVelocity = r.real("sleepAngularVelocity");
  p.sleepTime = r.real("sleepTime");
  p.numThreads = r.u32("numThreads");
  m_image.simulatedTime = r.f64("simulatedTime");
  if (m_version >= 2) p.enableShockPropagation = r.u8("enableShockPropagation") != 0;
  if (m_version >= 3) p.measureStages = r.u8("measureStages") != 0;
  if (!r.ok()) return false;
  if (p.timeStep > PFX_MAX_TIME_STEP) {
    std::ostringstream text;
    text << p.timeStep << " s above PFX_MAX_TIME_STEP (" << PFX_MAX_TIME_STEP << " s)";
    return r.fail(PFX_ERR_OUT_OF_RANGE, "timeStep", text.str());
  }
  if (p.subStep > PFX_MAX_SUB_STEPS) {
    return r.fail(PFX_ERR_OUT_OF_RANGE, "subStep",
                  std::to_string(p.subStep) + " above " + std::to_string(PFX_MAX_SUB_STEPS));
  }
  if (p.iteration > PFX_MAX_ITERATIONS) {
    return r.fail(PFX_ERR_OUT_OF_RANGE, "iteration",
                  std::to_string(p.iteration) + " above " + std::to_string(PFX_MAX_ITERATIONS));
  }
  if (const PfxInt32 err = PfxSerializeAccess::checkWorldParam(p); err != PFX_OK) {
    return r.fail(err, nullptr, "PfxWorld::initialize rejects these parameters");
  }
  if (!(m_image.simulatedTime >= 0)) {
    return r.fail(PFX_ERR_INVALID_VALUE, "simulatedTime", "is negative");
  }
  return true;
}

bool Parser::convexMesh(PfxConvexMesh& mesh) {
  mesh.m_numVerts = r.u8("numVerts");
  mesh.m_numFacets = r.u8("numFacets");
  mesh.m_numEdges = r.u8("numEdges");
  mesh.m_numFaces = r.u8("numFaces");
  if (!r.ok()) return false;
  if (mesh.m_numVerts < 4 || mesh.m_numVerts > PFX_CONVEX_MESH_MAX_VERTICES ||
      mesh.m_numFacets < 4 || mesh.m_numFacets > PFX_CONVEX_MESH_MAX_FACETS ||
      mesh.m_numEdges > PFX_CONVEX_MESH_MAX_EDGES || mesh.m_numFaces < 4 ||
      mesh.m_numFaces > mesh.m_numFacets) {
    return r.fail(PFX_ERR_OUT_OF_RANGE, "counts",
                  "vertices, facets, edges or faces outside 4..34, 4..64, 0..96, 4..facets");
  }
  const auto vertexId = [&](const char* field) {
    const PfxUInt8 id = r.u8(field);
    if (r.ok() && id >= mesh.m_numVerts) {
      r.fail(PFX_ERR_OUT_OF_RANGE, field,
             "names vertex " + std::to_string(id) + " of " + std::to_string(mesh.m_numVerts));
    }
    return id;
  };
  for (PfxUInt32 i = 0; i < mesh.m_numVerts; ++i) mesh.m_verts[i] = r.vec3("verts");
  for (PfxUInt32 i = 0; i < mesh.m_numFacets; ++i) {
    for (PfxUInt8& id : mesh.m_facetVertIds[i]) id = vertexId("facetVertIds");
  }
  for (PfxUInt32 i = 0; i < mesh.m_numEdges; ++i) {
    for (PfxUInt8& id : mesh.m_edgeVertIds[i]) id = vertexId("edgeVertIds");
  }
  const PfxUInt8 numFaceVertIds = r.u8("numFaceVertIds");
  if (!r.ok()) return false;
  if (numFaceVertIds > PFX_CONVEX_MESH_MAX_FACE_VERTICES) {
    return r.fail(PFX_ERR_OUT_OF_RANGE, "numFaceVertIds",
                  "is " + std::to_string(numFaceVertIds) + ", more than " +
                      std::to_string(PFX_CONVEX_MESH_MAX_FACE_VERTICES));
  }
  for (PfxUInt32 i = 0; i < mesh.m_numFaces; ++i) {
    mesh.m_faceNormals[i] = r.vec3("faceNormals");
    mesh.m_facePlaneDist[i] = r.real("facePlaneDist");
    mesh.m_faceFirstVert[i] = r.u8("faceFirstVert");
    mesh.m_faceNumVerts[i] = r.u8("faceNumVerts");
    if (r.ok() && (mesh.m_faceNumVerts[i] < 3 ||
                   mesh.m_faceFirstVert[i] + mesh.m_faceNumVerts[i] > numFaceVertIds)) {
      return r.fail(PFX_ERR_OUT_OF_RANGE, "faceNumVerts",
                    "face " + std::to_string(i) + " has fewer than 3 corners or ends past the " +
                        std::to_string(numFaceVertIds) + " face corners");
    }
  }
  for (PfxUInt32 i = 0; i < numFaceVertIds; ++i) mesh.m_faceVertIds[i] = vertexId("faceVertIds");
  mesh.m_aabbCenter = r.vec3("aabbCenter");
  mesh.m_aabbHalf = r.vec3("aabbHalf");
  return r.ok();
}

bool Parser::convexMeshes() {
  const PfxUInt32 n = r.count("count", kMinConvexMeshBytes);
  for (PfxUInt32 i = 0; i < n && r.ok(); ++i) {
    PfxTagScope tag(r, at("convex mesh", i));
    PfxConvexMesh* mesh = pfxNewConvexMesh();
    if (!mesh) return r.fail(PFX_ERR_OUT_OF_BUFFER, nullptr, "out of memory");
    m_image.convexMeshes.push_back(mesh);
    if (!convexMesh(*mesh)) return false;
  }
  return r.ok();
}

// Links of the hierarchy: an inner link names a later node (nodes come before their
// children) that no other link names, no deeper than a descent's stack allows, and a leaf
// names triangles of an island.
bool Parser::largeMeshLinks(PfxLargeTriMesh& mesh) {
  std::vector<PfxUInt8> depth(mesh.m_numNodes, 0);
  std::vector<PfxUInt8> named(mesh.m_numNodes, 0);
  const bool quantized = mesh.m_quantizedNodes != nullptr;
  for (PfxUInt32 i = 0; i < mesh.m_numNodes; ++i) {
    PfxUInt32* links = quantized ? mesh.m_quantizedNodes[i].m_links : mesh.m_nodes[i].m_links;
    for (PfxUInt32 c = 0; c < PFX_LARGE_MESH_NODE_WIDTH; ++c) {
      const PfxUInt32 link = links[c] = r.u32("node links");
      if (!r.ok()) return false;
      const std::string where = "node " + std::to_string(i) + " slot " + std::to_string(c);
      if (link == PFX_LARGE_MESH_EMPTY_LINK) continue;
      if (pfxLargeMeshIsLeaf(link)) {
        const PfxUInt32 island = pfxLargeMeshLeafIsland(link);
        if (island >= mesh.m_numIslands ||
            pfxLargeMeshLeafOffset(link) + pfxLargeMeshLeafCount(link) >
                mesh.m_islands[island].m_numTriangles) {
          return r.fail(PFX_ERR_OUT_OF_RANGE, "node links",
                        where + " names triangles outside the islands");
        }
        continue;
      }
      if (link <= i || link >= mesh.m_numNodes || named[link] ||
          depth[i] + 1u >= PFX_LARGE_MESH_MAX_DEPTH) {
        return r.fail(PFX_ERR_OUT_OF_RANGE, "node links",
                      where + " names node " + std::to_string(link) +
                          ", which is not a later node of this mesh named once, within depth " +
                          std::to_string(PFX_LARGE_MESH_MAX_DEPTH));
      }
      named[link] = 1;
      depth[link] = static_cast<PfxUInt8>(depth[i] + 1);
    }
  }
  return true;
}

bool Parser::largeMesh(PfxLargeTriMesh& mesh) {
  mesh.m_flags = r.u32("flags");
  const PfxUInt8 storageBits = r.u8("storage");
  mesh.m_numVertices = r.u32("numVertices");
  mesh.m_numTriangles = r.u32("numTriangles");
  mesh.m_numSourceTriangles = r.u32("numSourceTriangles");
  mesh.m_numIslands = r.u32("numIslands");
  mesh.m_numNodes = r.u32("numNodes");
  mesh.m_thickness = r.real("thickness");
  mesh.m_quantOrigin = r.vec3("quantOrigin");
  mesh.m_quantStep = r.vec3("quantStep");
  if (!r.ok()) return false;
  const PfxLargeMeshStorage storage{(storageBits & 1) != 0, (storageBits & 2) != 0,
                                    (storageBits & 4) != 0};
  constexpr PfxUInt32 kKnownMeshFlags =
      PFX_MESH_FLAG_USE_BVH | PFX_MESH_FLAG_USE_QUANTIZED | PFX_MESH_FLAG_HIGH_QUALITY;
  if ((mesh.m_flags & ~kKnownMeshFlags) != 0 || storageBits > 7 ||
      storage.quantized != ((mesh.m_flags & PFX_MESH_FLAG_USE_QUANTIZED) != 0)) {
    return r.fail(PFX_ERR_INVALID_FLAG, "flags", "unknown flags, or storage that they contradict");
  }
  if (mesh.m_numVertices == 0 || mesh.m_numTriangles == 0 || mesh.m_numIslands == 0 ||
      mesh.m_numIslands > PFX_LARGE_MESH_MAX_ISLANDS || mesh.m_numIslands > mesh.m_numTriangles ||
      mesh.m_numNodes == 0 || mesh.m_numSourceTriangles < mesh.m_numTriangles) {
    return r.fail(PFX_ERR_OUT_OF_RANGE, "counts",
                  "no vertices, triangles, islands or nodes, too many islands, or fewer source "
                  "triangles than triangles");
  }
  if (!(mesh.m_thickness >= 0) || (storage.quantized && !(mesh.m_quantStep.minCoeff() > 0))) {
    return r.fail(PFX_ERR_INVALID_VALUE, "thickness",
                  "a negative thickness or a quantization step that is not positive");
  }
  const PfxUInt64 realBytes = r.realBytes();
  const PfxUInt64 bytes = 3ull * mesh.m_numVertices * (storage.quantized ? 2 : realBytes) +
                          3ull * mesh.m_numTriangles * (storage.cornerOffsets ? 2 : 4) +
                          PfxUInt64(mesh.m_numTriangles) * ((storage.sourceOffsets ? 2 : 4) + 1) +
                          16ull * mesh.m_numIslands + 16ull * mesh.m_numNodes;
  if (bytes > r.remaining()) {
    return r.fail(PFX_ERR_OUT_OF_RANGE, "counts",
                  "the arrays need " + std::to_string(bytes) + " bytes, but only " +
                      std::to_string(r.remaining()) + " are left");
  }
  mesh.m_numDroppedTriangles = mesh.m_numSourceTriangles - mesh.m_numTriangles;
  if (pfxAllocateLargeTriMeshArrays(mesh, storage) != PFX_OK) {
    return r.fail(PFX_ERR_OUT_OF_BUFFER, nullptr, "out of memory");
  }
  for (PfxUInt64 i = 0; i < 3ull * mesh.m_numVertices; ++i) {
    if (storage.quantized) {
      mesh.m_quantizedVertices[i] = r.u16("vertices");
    } else {
      mesh.m_vertices[i] = r.real("vertices");
    }
  }
  // Corners and sources are read now and checked once the islands are known.
  for (PfxUInt64 i = 0; i < 3ull * mesh.m_numTriangles; ++i) {
    if (storage.cornerOffsets) {
      mesh.m_triangleOffsets[i] = r.u16("triangles");
    } else {
      mesh.m_triangleVertices[i] = r.u32("triangles");
    }
  }
  for (PfxUInt32 t = 0; t < mesh.m_numTriangles; ++t) {
    if (storage.sourceOffsets) {
      mesh.m_triangleSourceOffsets[t] = r.u16("sources");
    } else {
      mesh.m_triangleSourceIds[t] = r.u32("sources");
    }
  }
  for (PfxUInt32 t = 0; t < mesh.m_numTriangles; ++t) {
    mesh.m_edgeFlags[t] = r.u8("edgeFlags");
    if (r.ok() && mesh.m_edgeFlags[t] > 63) {
      return r.fail(PFX_ERR_INVALID_FLAG, "edgeFlags", "triangle " + std::to_string(t));
    }
  }
  PfxUInt32 nextTriangle = 0;
  for (PfxUInt32 i = 0; i < mesh.m_numIslands; ++i) {
    PfxLargeMeshIsland& island = mesh.m_islands[i];
    island.m_firstTriangle = r.u32("islands");
    island.m_baseVertex = r.u32("islands");
    island.m_baseSource = r.u32("islands");
    island.m_numTriangles = r.u32("islands");
    if (!r.ok()) return false;
    // Islands tile the triangles in order, which the search for a triangle's island needs.
    if (island.m_firstTriangle != nextTriangle || island.m_numTriangles == 0 ||
        island.m_numTriangles > PFX_LARGE_MESH_MAX_TRIANGLES_PER_ISLAND ||
        island.m_numTriangles > mesh.m_numTriangles - nextTriangle) {
      return r.fail(PFX_ERR_OUT_OF_RANGE, "islands",
                    "island " + std::to_string(i) + " does not follow on from the one before it");
    }
    nextTriangle += island.m_numTriangles;
    for (PfxUInt32 t = island.m_firstTriangle; t < nextTriangle; ++t) {
      PfxUInt32 corners[3];
      pfxLargeMeshCorners(mesh, island, t, corners);
      const PfxUInt64 source =
          storage.sourceOffsets ? PfxUInt64(island.m_baseSource) + mesh.m_triangleSourceOffsets[t]
                                : mesh.m_triangleSourceIds[t];
      // A base near 2^32 wraps the corner it adds to: take the sum before it wraps.
      const PfxUInt64 base = storage.cornerOffsets ? island.m_baseVertex : 0;
      for (int k = 0; k < 3; ++k) {
        const PfxUInt64 corner =
            storage.cornerOffsets ? base + mesh.m_triangleOffsets[3 * t + k] : corners[k];
        if (corner >= mesh.m_numVertices) {
          return r.fail(PFX_ERR_OUT_OF_RANGE, "triangles",
                        "triangle " + std::to_string(t) + " names vertex " +
                            std::to_string(corner) + " of " + std::to_string(mesh.m_numVertices));
        }
      }
      if (source >= mesh.m_numSourceTriangles) {
        return r.fail(PFX_ERR_OUT_OF_RANGE, "sources",
                      "triangle " + std::to_string(t) + " came from triangle " +
                          std::to_string(source) + " of " +
                          std::to_string(mesh.m_numSourceTriangles));
      }
    }
  }
  if (nextTriangle != mesh.m_numTriangles) {
    return r.fail(PFX_ERR_OUT_OF_RANGE, "islands", "they do not hold every triangle");
  }
  if (!largeMeshLinks(mesh)) return false;
  // The node bounds and the mesh's bounds follow from the vertices: recomputed, not read.
  pfxRefitLargeTriMesh(mesh);
  return true;
}

bool Parser::largeMeshes() {
  const PfxUInt32 n = r.count("count", kMinLargeMeshBytes);
  for (PfxUInt32 i = 0; i < n && r.ok(); ++i) {
    PfxTagScope tag(r, at("large mesh", i));
    PfxLargeTriMesh* mesh = pfxNewLargeTriMesh();
    if (!mesh) return r.fail(PFX_ERR_OUT_OF_BUFFER, nullptr, "out of memory");
    m_image.largeMeshes.push_back(mesh);
    if (!largeMesh(*mesh)) return false;
  }
  return r.ok();
}

bool Parser::shape(PfxShape& shape) {
  shape.reset();
  const PfxUInt8 type = r.u8("type");
  const PfxVector3 offsetPosition = r.vec3("offsetPosition");
  const PfxQuat offsetOrientation = r.quat("offsetOrientation");
  if (!r.ok()) return false;
  const auto meshIndex = [&](std::size_t count) {
    const PfxUInt32 index = r.u32("mesh");
    if (r.ok() && index >= count) {
      r.fail(PFX_ERR_OUT_OF_RANGE, "mesh",
             "names mesh " + std::to_string(index) + " of " + std::to_string(count));
    }
    return index;
  };
  switch (type) {
    case kPfxShapeSphere:
      shape.setSphere(PfxSphere(r.real("radius")));
      break;
    case kPfxShapeBox:
      shape.setBox(PfxBox(r.vec3("half")));
      break;
    case kPfxShapeCapsule: {
      const PfxFloat halfLength = r.real("halfLength");
      shape.setCapsule(PfxCapsule(halfLength, r.real("radius")));
      break;
    }
    case kPfxShapeCylinder: {
      const PfxFloat halfLength = r.real("halfLength");
      shape.setCylinder(PfxCylinder(halfLength, r.real("radius")));
      break;
    }
    case kPfxShapeConvexMesh: {
      const PfxUInt32 index = meshIndex(m_image.convexMeshes.size());
      if (!r.ok()) return false;
      shape.setConvexMesh(m_image.convexMeshes[index]);
      break;
    }
    case kPfxShapeLargeTriMesh: {
      const PfxUInt32 index = meshIndex(m_image.largeMeshes.size());
      if (!r.ok()) return false;
      shape.setLargeTriMesh(m_image.largeMeshes[index]);
      break;
    }
    default:
      return r.fail(PFX_ERR_INVALID_FLAG, "type", "is " + std::to_string(type));
  }
  shape.setOffsetPosition(offsetPosition);
  shape.setOffsetOrientation(offsetOrientation);
  if (!r.ok()) return false;
  if (const PfxInt32 err = shape.validate(); err != PFX_OK) {
    return r.fail(err, nullptr, "PfxShape::validate rejects it");
  }
  return true;
}

bool Parser::bodies() {
  const PfxUInt32 n = r.count("count", kMinBodyBytes);
  if (!r.ok()) return false;
  m_image.states.resize(n);
  m_image.bodies.resize(n);
  m_image.forces.resize(n);
  m_image.torques.resize(n);
  m_image.firstShape.assign(1, 0);
  m_image.firstShape.reserve(n + 1);
  for (PfxUInt32 id = 0; id < n; ++id) {
    PfxTagScope tag(r, at("body", id));
    PfxRigidState& state = m_image.states[id];
    {
      PfxTagScope stateTag(r, "state");
      state.reset();
      state.setPosition(r.vec3("position"));
      state.setOrientation(r.quat("orientation"));
      state.setLinearVelocity(r.vec3("linearVelocity"));
      state.setAngularVelocity(r.vec3("angularVelocity"));
      if (m_version >= 2) {
        const PfxQuat orientationCarry = r.quat("orientationCarry");
        const PfxVector3 angularVelocityCarry = r.vec3("angularVelocityCarry");
        // What the writer's rounding left out means nothing in another precision.
        if (r.realBytes() == sizeof(PfxFloat)) {
          state.setRotation(state.getOrientation(), orientationCarry, state.getAngularVelocity(),
                            angularVelocityCarry);
        }
      }
      state.setRigidBodyId(r.u32("rigidBodyId"));
      state.setContactFilterSelf(r.u32("contactFilterSelf"));
      state.setContactFilterTarget(r.u32("contactFilterTarget"));
      const PfxUInt16 sleepCount = r.u16("sleepCount");
      const PfxUInt8 motionType = r.u8("motionType");
      const PfxUInt8 sleeping = r.u8("sleeping");
      if (!r.ok()) return false;
      if (motionType >= kPfxMotionTypeCount || sleeping > 1) {
        return r.fail(PFX_ERR_INVALID_FLAG, "motionType", "unknown motion type or sleep flag");
      }
      if (state.getRigidBodyId() != id) {
        return r.fail(PFX_ERR_OUT_OF_RANGE, "rigidBodyId",
                      "is " + std::to_string(state.getRigidBodyId()) +
                          "; it must be the body's "
                          "index");
      }
      state.setMotionType(static_cast<PfxMotionType>(motionType));
      PfxSerializeAccess::setSleep(state, sleeping != 0, sleepCount);
    }
    PfxRigidBody& body = m_image.bodies[id];
    {
      PfxTagScope bodyTag(r, "body");
      body.reset();
      body.setMass(r.real("mass"));
      body.setInertia(r.mat3("inertia"));
      body.setFriction(r.real("friction"));
      body.setRestitution(r.real("restitution"));
    }
    m_image.forces[id] = r.vec3("force");
    m_image.torques[id] = r.vec3("torque");
    if (!r.ok()) return false;
    if (const PfxInt32 err = PfxSerializeAccess::checkBody(state, body); err != PFX_OK) {
      const char* bodyProblem = state.isValid() && pfxMotionTypeIsDynamic(state.getMotionType())
                                    ? body.problem()
                                    : nullptr;
      return r.fail(err, "state",
                    bodyProblem ? std::string("PfxWorld rejects its body: ") + bodyProblem
                                : "PfxWorld rejects it: a position or velocity not finite, a "
                                  "speed beyond kPfxMaxLinearSpeed or kPfxMaxAngularSpeed (1e5) "
                                  "for a body forces do not move, not a unit orientation, or a "
                                  "mass, inertia, friction or restitution it cannot simulate");
    }
    const PfxUInt8 count = r.u8("numShapes");
    if (!r.ok()) return false;
    if (count == 0 || count > PFX_MAX_SHAPES_PER_COLLIDABLE) {
      return r.fail(PFX_ERR_OUT_OF_RANGE, "numShapes", "is " + std::to_string(count));
    }
    for (PfxUInt32 i = 0; i < count; ++i) {
      PfxTagScope shapeTag(r, at("shape", i));
      m_image.shapes.emplace_back();
      if (!shape(m_image.shapes.back())) return false;
    }
    m_image.firstShape.push_back(static_cast<PfxUInt32>(m_image.shapes.size()));
  }
  return true;
}

bool Parser::jointConstraint(PfxJointConstraint& c) {
  c.m_lock = r.u8("lock");
  c.m_drive = r.u8("drive");
  c.m_rowType = r.u8("rowType");
  c.m_driveRowUsed = r.u8("driveRowUsed");
  c.m_movableLowerLimit = r.real("movableLowerLimit");
  c.m_movableUpperLimit = r.real("movableUpperLimit");
  c.m_bias = r.real("bias");
  c.m_weight = r.real("weight");
  c.m_damping = r.real("damping");
  c.m_friction = r.real("friction");
  c.m_driveTarget = r.real("driveTarget");
  c.m_driveMaxForce = r.real("driveMaxForce");
  c.m_constraintRow = r.row("constraintRow");
  c.m_driveRow = r.row("driveRow");
  c.m_pushRhs = r.real("pushRhs");
  c.m_pushImpulse = r.real("pushImpulse");
  c.m_position = r.real("position");
  c.m_treeResponse[0] = r.real("treeResponse");
  c.m_treeResponse[1] = r.real("treeResponse");
  if (r.ok() && (c.m_rowType > kPfxJointRowLimit || c.m_driveRowUsed > 1)) {
    return r.fail(PFX_ERR_INVALID_FLAG, "rowType", "unknown row type or drive row flag");
  }
  return r.ok();
}

bool Parser::joints() {
  const PfxUInt32 n = r.count("count", kMinJointBytes);
  if (!r.ok()) return false;
  m_image.joints.resize(n);
  for (PfxUInt32 j = 0; j < n; ++j) {
    PfxTagScope tag(r, at("joint", j));
    PfxJoint& joint = m_image.joints[j];
    joint.reset();
    for (PfxUInt32 axis = 0; axis < 6; ++axis) {
      PfxTagScope axisTag(r, at("axis", axis));
      if (!jointConstraint(joint.m_constraints[axis])) return false;
    }
    joint.m_frameA = r.mat3("frameA");
    joint.m_frameB = r.mat3("frameB");
    joint.m_anchorA = r.vec3("anchorA");
    joint.m_anchorB = r.vec3("anchorB");
    joint.m_rigidBodyIdA = r.u32("rigidBodyIdA");
    joint.m_rigidBodyIdB = r.u32("rigidBodyIdB");
    joint.m_active = r.u8("active");
    joint.m_type = r.u8("type");
    joint.m_rotation = r.u8("rotation");
    joint.m_padding = 0;
    joint.m_armA = r.vec3("armA");
    joint.m_armB = r.vec3("armB");
    for (PfxVector3& axis : joint.m_axes) axis = r.vec3("axes");
    if (!r.ok()) return false;
    if (joint.m_rigidBodyIdA >= m_image.numBodies() ||
        joint.m_rigidBodyIdB >= m_image.numBodies()) {
      return r.fail(
          PFX_ERR_OUT_OF_RANGE, "rigidBodyIdA",
          "a body id is not below the " + std::to_string(m_image.numBodies()) + " bodies");
    }
    if (joint.m_active > 1) return r.fail(PFX_ERR_INVALID_FLAG, "active", "is neither 0 nor 1");
    if (const PfxInt32 err = pfxCheckJoint(joint); err != PFX_OK) {
      return r.fail(err, nullptr, "pfxCheckJoint rejects it");
    }
  }
  return true;
}

bool Parser::couplings() {
  const PfxUInt32 n = r.count("count", kMinCouplingBytes);
  if (!r.ok()) return false;
  m_image.jointCouplings.resize(n);
  for (PfxUInt32 k = 0; k < n; ++k) {
    PfxTagScope tag(r, at("coupling", k));
    PfxJointCoupling& c = m_image.jointCouplings[k];
    c.reset();
    c.m_leaderJointId = r.u32("leaderJointId");
    c.m_followerJointId = r.u32("followerJointId");
    c.m_leaderAxis = r.u8("leaderAxis");
    c.m_followerAxis = r.u8("followerAxis");
    c.m_active = r.u8("active");
    c.m_numBodies = r.u8("numBodies");
    c.m_multiplier = r.real("multiplier");
    c.m_offset = r.real("offset");
    c.m_bias = r.real("bias");
    c.m_maxImpulseForce = r.real("maxImpulseForce");
    c.m_leaderPosition = r.real("leaderPosition");
    c.m_followerPosition = r.real("followerPosition");
    c.m_row = r.row("row");
    if (!r.ok()) return false;
    if (c.m_numBodies > PFX_JOINT_COUPLING_MAX_BODIES || c.m_active > 1) {
      return r.fail(PFX_ERR_OUT_OF_RANGE, "numBodies", "more than 4 bodies, or active not 0/1");
    }
    for (PfxUInt32 b = 0; b < c.m_numBodies; ++b) {
      c.m_bodies[b].m_linear = r.vec3("bodies");
      c.m_bodies[b].m_angular = r.vec3("bodies");
      c.m_bodies[b].m_rigidBodyId = r.u32("bodies");
      if (r.ok() && c.m_bodies[b].m_rigidBodyId >= m_image.numBodies()) {
        return r.fail(PFX_ERR_OUT_OF_RANGE, "bodies", "names a body that is not in the file");
      }
    }
    c.m_pushRhs = r.real("pushRhs");
    c.m_pushImpulse = r.real("pushImpulse");
    c.m_error = r.real("error");
    if (!r.ok()) return false;
    if (const PfxInt32 err =
            pfxCheckJointCoupling(c, m_image.joints.data(), PfxUInt32(m_image.joints.size()));
        err != PFX_OK) {
      return r.fail(err, nullptr, "pfxCheckJointCoupling rejects it");
    }
  }
  return true;
}

bool Parser::exclusions() {
  const PfxUInt32 n = r.count("count", 8);
  if (!r.ok()) return false;
  m_image.excludedPairKeys.resize(n);
  for (PfxUInt32 i = 0; i < n; ++i) {
    const PfxUInt64 key = m_image.excludedPairKeys[i] = r.u64("keys");
    if (!r.ok()) return false;
    const PfxUInt32 a = PfxUInt32(key >> 32), b = PfxUInt32(key);
    if (a >= b || b >= m_image.numBodies() || (i > 0 && key <= m_image.excludedPairKeys[i - 1])) {
      return r.fail(PFX_ERR_OUT_OF_RANGE, "keys",
                    "pair " + std::to_string(i) +
                        " is not (A < B) of bodies in the file, or not "
                        "in increasing order");
    }
  }
  return true;
}

bool Parser::contactPoint(PfxContactPoint& p, PfxUInt32 idA, PfxUInt32 idB) {
  for (PfxConstraintRow& row : p.m_constraintRow) row = r.row("constraintRow");
  p.m_localPointA = r.vec3("localPointA");
  p.m_localPointB = r.vec3("localPointB");
  p.m_armA = r.vec3("armA");
  p.m_armB = r.vec3("armB");
  p.m_distance = r.real("distance");
  p.m_approachVelocity = r.real("approachVelocity");
  p.m_maxImpulse = r.real("maxImpulse");
  p.m_pushRhs = r.real("pushRhs");
  p.m_pushImpulse = r.real("pushImpulse");
  p.m_duration = r.u32("duration");
  p.m_shapeIdA = r.u8("shapeIdA");
  p.m_shapeIdB = r.u8("shapeIdB");
  p.m_padding = 0;
  p.m_triangleIndex = r.u32("triangleIndex");
  for (PfxFloat& w : p.m_barycentric) w = r.real("barycentric");
  if (!r.ok()) return false;
  // The contact normal, which the refresh and the solver take as it is: a normal of
  // (3.4e38, 1, 0) turned the bodies of its pair NaN in the first step.
  if (!(std::abs(p.m_constraintRow[0].m_normal.squaredNorm() - 1) <= PfxFloat(1e-3))) {
    return r.fail(PFX_ERR_INVALID_VALUE, "constraintRow", "the contact normal is not of unit length");
  }
  // A point lies on its shapes, which reach no farther than kPfxMaxShapeReach from their
  // bodies: a saved point 6.3e29 m from its body gave its pair lever arms whose squares
  // overflowed, and the body, with the pendulums jointed and coupled to it, turned NaN in
  // the first step.
  if (!(p.m_localPointA.cwiseAbs().maxCoeff() <= kPfxMaxShapeReach)) {
    return r.fail(PFX_ERR_OUT_OF_RANGE, "localPointA",
                  "lies beyond kPfxMaxShapeReach of its body");
  }
  if (!(p.m_localPointB.cwiseAbs().maxCoeff() <= kPfxMaxShapeReach)) {
    return r.fail(PFX_ERR_OUT_OF_RANGE, "localPointB",
                  "lies beyond kPfxMaxShapeReach of its body");
  }
  if (p.m_shapeIdA >= numShapes(idA) || p.m_shapeIdB >= numShapes(idB)) {
    return r.fail(PFX_ERR_OUT_OF_RANGE, "shapeIdA", "names a shape its body does not have");
  }
  if (p.m_triangleIndex == PFX_CONTACT_NO_TRIANGLE) return true;
  // The triangle belongs to the large mesh of either side; a point between two shapes
  // that are not large meshes has none.
  PfxUInt32 limit = 0;
  for (const PfxShape* s : {&bodyShape(idA, p.m_shapeIdA), &bodyShape(idB, p.m_shapeIdB)}) {
    if (s->getType() == kPfxShapeLargeTriMesh) {
      limit = std::max(limit, s->getLargeTriMesh()->m_numTriangles);
    }
  }
  if (p.m_triangleIndex >= limit) {
    return r.fail(PFX_ERR_OUT_OF_RANGE, "triangleIndex",
                  "is " + std::to_string(p.m_triangleIndex) + ", but the mesh has " +
                      std::to_string(limit) + " triangles");
  }
  return true;
}

bool Parser::manifold(PfxContactManifold& manifold) {
  const PfxUInt32 idA = r.u32("rigidBodyIdA");
  const PfxUInt32 idB = r.u32("rigidBodyIdB");
  const PfxUInt8 numContacts = r.u8("numContacts");
  if (!r.ok()) return false;
  if (idA >= m_image.numBodies() || idB >= m_image.numBodies() ||
      numContacts > PFX_NUM_CONTACTS_PER_MANIFOLD) {
    return r.fail(PFX_ERR_OUT_OF_RANGE, "rigidBodyIdA",
                  "a body that is not in the file, or more than 4 points");
  }
  manifold.reset(idA, idB);
  manifold.setCompositeFriction(r.real("compositeFriction"));
  manifold.setCompositeRestitution(r.real("compositeRestitution"));
  for (PfxUInt32 i = 0; i < numContacts; ++i) {
    for (PfxUInt32 j = 0; j < numContacts; ++j) {
      manifold.setNormalCoupling(i, j, r.real("normalCoupling"));
    }
  }
  for (PfxUInt32 i = 0; i < numContacts; ++i) {
    PfxTagScope tag(r, at("point", i));
    if (!contactPoint(manifold.getContactPoint(i), idA, idB)) return false;
  }
  PfxSerializeAccess::setNumContacts(manifold, numContacts);
  return r.ok();
}

// A list of pairs: sorted keys of bodies in the file (A < B), each naming a manifold in use
// that no other pair names, made for the same two bodies.
bool Parser::pairList(const char* name, std::vector<PfxBroadphasePair>& pairs,
                      std::vector<PfxUInt8>& manifoldUse) {
  PfxTagScope tag(r, name);
  const PfxUInt32 n = r.count("count", kPairBytes);
  if (!r.ok()) return false;
  pairs.resize(n);
  for (PfxUInt32 i = 0; i < n; ++i) {
    PfxBroadphasePair& pair = pairs[i];
    pair.key = r.u64("key");
    pair.data[0] = r.u32("contactId");
    pair.data[1] = r.u32("flags");
    if (!r.ok()) return false;
    const std::string where = "pair " + std::to_string(i);
    const PfxUInt32 a = pfxGetObjectIdA(pair), b = pfxGetObjectIdB(pair);
    if (a >= b || b >= m_image.numBodies() || (i > 0 && pair.key <= pairs[i - 1].key)) {
      return r.fail(PFX_ERR_OUT_OF_RANGE, "key",
                    where + " is not (A < B) of bodies in the file, or not in increasing order");
    }
    if (pfxGetMotionTypeA(pair) >= kPfxMotionTypeCount ||
        pfxGetMotionTypeB(pair) >= kPfxMotionTypeCount ||
        pfxGetNumConstraints(pair) > PFX_NUM_CONTACTS_PER_MANIFOLD) {
      return r.fail(PFX_ERR_INVALID_FLAG, "flags",
                    where + ": unknown motion type or more than 4 constraints");
    }
    const PfxUInt32 contactId = pfxGetContactId(pair);
    if (contactId >= manifoldUse.size() || manifoldUse[contactId] != 0) {
      return r.fail(PFX_ERR_OUT_OF_RANGE, "contactId",
                    where + " names manifold " + std::to_string(contactId) +
                        ", which is not there, free, or another pair's");
    }
    manifoldUse[contactId] = 2;
    const PfxContactManifold& manifold = m_image.manifolds[contactId];
    if (manifold.getRigidBodyIdA() != a || manifold.getRigidBodyIdB() != b) {
      return r.fail(PFX_ERR_OUT_OF_RANGE, "contactId", where + " names a manifold of other bodies");
    }
  }
  return true;
}

bool Parser::contacts() {
  const PfxUInt32 numManifolds = r.count("numManifolds", 0);
  const PfxUInt32 numFree = r.count("numFree", 4);
  if (!r.ok()) return false;
  if (numFree > numManifolds) {
    return r.fail(PFX_ERR_OUT_OF_RANGE, "numFree", "is more than there are manifolds");
  }
  if (PfxUInt64(numManifolds - numFree) * kMinManifoldBytes + 4ull * numFree > r.remaining()) {
    return r.fail(PFX_ERR_OUT_OF_RANGE, "numManifolds", "is more than the bytes left can hold");
  }
  // 1: free, 2: a pair's.
  std::vector<PfxUInt8> manifoldUse(numManifolds, 0);
  m_image.freeManifolds.resize(numFree);
  for (PfxUInt32 i = 0; i < numFree; ++i) {
    const PfxUInt32 id = m_image.freeManifolds[i] = r.u32("freeManifolds");
    if (!r.ok()) return false;
    if (id >= numManifolds || manifoldUse[id] != 0) {
      return r.fail(PFX_ERR_OUT_OF_RANGE, "freeManifolds",
                    "slot " + std::to_string(id) + " is not there or listed twice");
    }
    manifoldUse[id] = 1;
  }
  // Free slots are stored empty: their content is never read again.
  m_image.manifolds.resize(numManifolds);
  for (PfxUInt32 i = 0; i < numManifolds; ++i) {
    m_image.manifolds[i].reset(0, 0);
    if (manifoldUse[i] == 1) continue;
    PfxTagScope tag(r, at("manifold", i));
    if (!manifold(m_image.manifolds[i])) return false;
  }
  if (!pairList("awake pairs", m_image.pairs, manifoldUse) ||
      !pairList("sleeping pairs", m_image.sleepingPairs, manifoldUse)) {
    return false;
  }
  // A pair is awake or asleep, not both: waking would merge the two into one list.
  const auto byKey = [](const PfxBroadphasePair& a, const PfxBroadphasePair& b) {
    return a.key < b.key;
  };
  std::vector<PfxBroadphasePair> both;
  std::set_intersection(m_image.pairs.begin(), m_image.pairs.end(), m_image.sleepingPairs.begin(),
                        m_image.sleepingPairs.end(), std::back_inserter(both), byKey);
  if (!both.empty()) {
    PfxTagScope tag(r, "sleeping pairs");
    return r.fail(PFX_ERR_OUT_OF_RANGE, "key",
                  "bodies " + std::to_string(pfxGetObjectIdA(both[0])) + " and " +
                      std::to_string(pfxGetObjectIdB(both[0])) + " are also an awake pair");
  }
  return true;
}

}  // namespace

PfxSerializeImage::~PfxSerializeImage() {
  for (PfxConvexMesh* mesh : convexMeshes) pfxDeleteConvexMesh(mesh);
  for (PfxLargeTriMesh* mesh : largeMeshes) pfxDeleteLargeTriMesh(mesh);
}

PfxSerializeCapacity PfxSerializeImage::capacity() const {
  PfxSerializeCapacity c;
  c.numRigidBodies = numBodies();
  for (PfxUInt32 id = 0; id < numBodies(); ++id) {
    const PfxUInt32 count = firstShape[id + 1] - firstShape[id];
    if (count > 1) c.numShapes += count;
  }
  c.numJoints = static_cast<PfxUInt32>(joints.size());
  c.numJointCouplings = static_cast<PfxUInt32>(jointCouplings.size());
  c.numContactPairs = static_cast<PfxUInt32>(pairs.size());
  c.numSleepingPairs = static_cast<PfxUInt32>(sleepingPairs.size());
  c.numContactManifolds = static_cast<PfxUInt32>(manifolds.size());
  c.numFreeManifolds = static_cast<PfxUInt32>(freeManifolds.size());
  c.numExcludedPairs = static_cast<PfxUInt32>(excludedPairKeys.size());
  c.numConvexMeshes = static_cast<PfxUInt32>(convexMeshes.size());
  c.numLargeMeshes = static_cast<PfxUInt32>(largeMeshes.size());
  return c;
}

PfxInt32 pfxDecodeSerialized(const std::vector<PfxUInt8>& bytes, PfxSerializeImage& image,
                             PfxSerializeError& error, PfxSerializeUpdateFunc update,
                             void* userData) {
  std::vector<std::string> tags;
  PfxByteReader file(bytes.data(), bytes.size(), 0, error, tags);
  std::size_t realBytes = 0;
  PfxUInt32 version = 0;
  {
    PfxTagScope tag(file, "header");
    const PfxUInt8* magic = file.take(sizeof(kPfxSerializeMagic), "magic");
    if (magic && std::memcmp(magic, kPfxSerializeMagic, sizeof(kPfxSerializeMagic)) != 0) {
      file.fail(PFX_ERR_INVALID_FLAG, "magic", "this is not a pfx world file");
    }
    version = file.u32("version");
    if (file.ok() && (version < PFX_SERIALIZE_OLDEST_VERSION || version > PFX_SERIALIZE_VERSION)) {
      file.fail(PFX_ERR_INVALID_FLAG, "version",
                "is " + std::to_string(version) + "; this build reads versions " +
                    std::to_string(PFX_SERIALIZE_OLDEST_VERSION) + " to " +
                    std::to_string(PFX_SERIALIZE_VERSION));
    }
    realBytes = file.u8("precision");
    if (file.ok() && realBytes != 4 && realBytes != 8) {
      file.fail(PFX_ERR_INVALID_FLAG, "precision",
                "is " + std::to_string(realBytes) + " bytes per real; 4 or 8 expected");
    }
    for (int i = 0; i < 3; ++i) {
      if (file.u8("reserved") != 0) file.fail(PFX_ERR_INVALID_FLAG, "reserved", "is not 0");
    }
    const PfxUInt64 bodyBytes = file.u64("body length");
    const PfxUInt64 checksum = file.u64("checksum");
    if (!file.ok()) return error.code;
    if (bodyBytes != file.remaining()) {
      file.fail(PFX_ERR_OUT_OF_BUFFER, "body length",
                "is " + std::to_string(bodyBytes) + " bytes, but " +
                    std::to_string(file.remaining()) + " follow");
      return error.code;
    }
    if (pfxSerializeChecksum(bytes.data() + kPfxSerializeHeaderBytes,
                             bytes.size() - kPfxSerializeHeaderBytes) != checksum) {
      file.fail(PFX_ERR_INVALID_VALUE, "checksum", "the body does not match it: the file changed");
      return error.code;
    }
  }
  PfxByteReader body(bytes.data() + kPfxSerializeHeaderBytes,
                     bytes.size() - kPfxSerializeHeaderBytes, realBytes, error, tags);
  struct Section {
    const char* tag;
    const char* name;
    bool (Parser::*parse)();
  };
  const Section sections[] = {
      {"PARM", "parameters", &Parser::param},
      {"CMSH", "convex meshes", &Parser::convexMeshes},
      {"LMSH", "large meshes", &Parser::largeMeshes},
      {"BODY", "bodies", &Parser::bodies},
      {"JOIN", "joints", &Parser::joints},
      {"CPLG", "joint couplings", &Parser::couplings},
      {"EXCL", "exclusions", &Parser::exclusions},
      {"CONT", "contacts", &Parser::contacts},
  };
  for (const Section& section : sections) {
    PfxTagScope tag(body, section.name);
    PfxByteReader inner(nullptr, 0, realBytes, error, tags);
    if (!body.section(section.tag, inner)) return error.code;
    Parser sectionParser(inner, image, version);
    if (!(sectionParser.*section.parse)() || !inner.finish(nullptr)) return error.code;
    if (update) {
      update(bytes.size() - body.remaining(), bytes.size(), userData);
    }
  }
  // The optional sections: a world's removed slots, then its particle groups.
  if (body.ok() && body.nextSectionIs("GONE")) {
    PfxTagScope tag(body, "removed slots");
    PfxByteReader inner(nullptr, 0, realBytes, error, tags);
    if (!body.section("GONE", inner)) return error.code;
    if (!pfxDecodeRemovals(inner, image) || !inner.finish(nullptr)) return error.code;
    if (update) update(bytes.size() - body.remaining(), bytes.size(), userData);
  }
  if (body.ok() && body.remaining() > 0) {
    PfxTagScope tag(body, "particle groups");
    PfxByteReader inner(nullptr, 0, realBytes, error, tags);
    if (!body.section("PART", inner)) return error.code;
    if (!pfxDecodeParticleGroups(inner, image) || !inner.finish(nullptr) ||
        !pfxCheckRemovedPins(inner, image)) {
      return error.code;
    }
    if (update) update(bytes.size() - body.remaining(), bytes.size(), userData);
  }
  body.finish("sections");
  return error.code;
}

}  // namespace pfx
