// A convex shape against a large mesh. Each triangle near the shape becomes a prism that
// reaches the mesh's thickness below its face, and meets the shape through the convex
// pair routines (separating axes or GJK/EPA, then face clipping). Two corrections follow,
// both along the face normal:
//   - one-sided: a prism never pushes a shape down through the mesh, so a result whose
//     normal points below the face, or whose points lie inside the face (a shape sunk
//     deeper than half the prism), is replaced by the face contact; a shape separated
//     from the prism on that side lies beneath the mesh and gets no contact from it;
//   - internal edges: a contact found on an edge shared with a flat or concave neighbour
//     (PFX_LARGE_MESH_EDGE_INTERNAL_*) would tilt its normal toward the neighbour and make
//     a sliding body bump over the seam; it is replaced by the face contact too, which the
//     neighbour's own face contact then continues without a jump.
// The face contact is the shape's supporting face along -normal clipped to the triangle's
// side planes, each point measured to the face plane.
#include <algorithm>
#include <cmath>

#include "base_level/collision/contact/pfx_clip_polygon.h"
#include "base_level/collision/contact/pfx_contact_pairs.h"
#include "base_level/collision/contact/pfx_convex_core.h"
#include "base_level/collision/pfx_large_tri_mesh_access.h"
#include "pfx/base_level/collision/pfx_contact_shapes.h"

namespace pfx {

namespace {

// A result within this cosine of the face normal is a face contact already.
constexpr PfxFloat kFaceNormalCosine = PfxFloat(1) - PfxFloat(1e-4);
// A prism is never thinner than this (m): a flat one has no inside for the pair routines.
constexpr PfxFloat kMinPrismThickness = PfxFloat(1e-4);
// Candidates gathered over the triangles before they are reduced to the best four.
constexpr PfxUInt32 kGatherCapacity = 48;

struct Triangle {
  PfxVector3 v[3];  // world
  PfxVector3 normal;
  PfxFloat edgeLength[3];  // edge i runs from v[i] to v[(i + 1) % 3]
  PfxFloat areaTwice;
  PfxUInt8 flags;
};

// The prism below the triangle as a convex mesh (6 vertices, top, bottom and three quads),
// in the world frame.
void buildPrism(const Triangle& tri, PfxFloat thickness, PfxConvexMesh& prism) {
  prism.m_numVerts = 6;
  prism.m_numFacets = 8;
  prism.m_numEdges = 9;
  prism.m_numFaces = 5;
  const PfxVector3 down = -tri.normal * thickness;
  for (int i = 0; i < 3; ++i) {
    prism.m_verts[i] = tri.v[i];
    prism.m_verts[i + 3] = tri.v[i] + down;
  }
  static const PfxUInt8 kFacets[8][3] = {{0, 1, 2}, {3, 5, 4}, {0, 3, 4}, {0, 4, 1},
                                         {1, 4, 5}, {1, 5, 2}, {2, 5, 3}, {2, 3, 0}};
  static const PfxUInt8 kEdges[9][2] = {{0, 1}, {1, 2}, {2, 0}, {3, 4}, {4, 5},
                                        {5, 3}, {0, 3}, {1, 4}, {2, 5}};
  // Loops counter-clockwise from outside: the top as given, the bottom reversed, and the
  // side of edge i down its first corner and up its second.
  static const PfxUInt8 kLoops[16] = {0, 1, 2, 3, 5, 4, 0, 3, 4, 1, 1, 4, 5, 2, 2, 5};
  std::copy(&kFacets[0][0], &kFacets[0][0] + 24, &prism.m_facetVertIds[0][0]);
  std::copy(&kEdges[0][0], &kEdges[0][0] + 18, &prism.m_edgeVertIds[0][0]);
  std::copy(kLoops, kLoops + 16, prism.m_faceVertIds);
  prism.m_faceVertIds[16] = 3;
  prism.m_faceVertIds[17] = 0;
  prism.m_faceFirstVert[0] = 0;
  prism.m_faceNumVerts[0] = 3;
  prism.m_faceFirstVert[1] = 3;
  prism.m_faceNumVerts[1] = 3;
  prism.m_faceNormals[0] = tri.normal;
  prism.m_faceNormals[1] = -tri.normal;
  for (int i = 0; i < 3; ++i) {
    prism.m_faceFirstVert[2 + i] = static_cast<PfxUInt8>(6 + 4 * i);
    prism.m_faceNumVerts[2 + i] = 4;
    prism.m_faceNormals[2 + i] =
        (tri.v[(i + 1) % 3] - tri.v[i]).cross(tri.normal) / tri.edgeLength[i];
  }
  for (int f = 0; f < 5; ++f) {
    prism.m_facePlaneDist[f] =
        prism.m_faceNormals[f].dot(prism.m_verts[prism.m_faceVertIds[prism.m_faceFirstVert[f]]]);
  }
  PfxVector3 lo = prism.m_verts[0], hi = prism.m_verts[0];
  for (int i = 1; i < 6; ++i) {
    lo = lo.cwiseMin(prism.m_verts[i]);
    hi = hi.cwiseMax(prism.m_verts[i]);
  }
  prism.m_aabbCenter = (lo + hi) * PfxFloat(0.5);
  prism.m_aabbHalf = (hi - lo) * PfxFloat(0.5);
}

// Corner weights of the point of the triangle's plane nearest to p, and for each edge
// whether p lies on it (within `tolerance`, measured in the plane).
void locate(const Triangle& tri, const PfxVector3& p, PfxFloat tolerance, PfxFloat weights[3],
            bool onEdge[3]) {
  const PfxVector3 e0 = tri.v[1] - tri.v[0];
  const PfxVector3 e1 = tri.v[2] - tri.v[0];
  const PfxVector3 d = p - tri.v[0];
  const PfxFloat d00 = e0.dot(e0), d01 = e0.dot(e1), d11 = e1.dot(e1);
  const PfxFloat d20 = d.dot(e0), d21 = d.dot(e1);
  const PfxFloat denom = d00 * d11 - d01 * d01;
  weights[1] = (d11 * d20 - d01 * d21) / denom;
  weights[2] = (d00 * d21 - d01 * d20) / denom;
  weights[0] = 1 - weights[1] - weights[2];
  // Edge i lies opposite corner (i + 2) % 3; that corner's weight times the height over
  // the edge is the distance from it.
  for (int i = 0; i < 3; ++i) {
    onEdge[i] = weights[(i + 2) % 3] * tri.areaTwice <= tolerance * tri.edgeLength[i];
  }
}

// The weights of a point clamped into the triangle, summing to one: what a contact point
// records so that it can be put back on the triangle later.
void clampWeights(PfxFloat weights[3]) {
  PfxFloat sum = 0;
  for (int k = 0; k < 3; ++k) {
    weights[k] = std::max(weights[k], PfxFloat(0));
    sum += weights[k];
  }
  for (int k = 0; k < 3; ++k) weights[k] = sum > 0 ? weights[k] / sum : PfxFloat(1) / 3;
}

// Gathers candidates from all triangles; when full, keeps the best four and goes on.
class Gatherer {
 public:
  void add(const PfxContactCandidate& c) {
    if (m_count == kGatherCapacity) reduce();
    m_items[m_count++] = c;
  }
  void reduce() {
    PfxUInt32 chosen[PFX_NUM_CONTACTS_PER_MANIFOLD];
    const PfxUInt32 n = pfxReduceContactCandidates(m_items, m_count, chosen);
    PfxContactCandidate kept[PFX_NUM_CONTACTS_PER_MANIFOLD];
    for (PfxUInt32 i = 0; i < n; ++i) kept[i] = m_items[chosen[i]];
    for (PfxUInt32 i = 0; i < n; ++i) m_items[i] = kept[i];
    m_count = n;
  }
  PfxUInt32 m_count = 0;
  PfxContactCandidate m_items[kGatherCapacity];
};

void addCandidate(Gatherer& gatherer, const Triangle& tri, PfxUInt32 triangleIndex,
                  const PfxVector3& normal, const PfxVector3& onMesh, const PfxVector3& onShape,
                  PfxFloat distance) {
  PfxContactCandidate c;
  c.m_normal = normal;
  c.m_pointA = onMesh;
  c.m_pointB = onShape;
  c.m_distance = distance;
  c.m_shapeIdA = c.m_shapeIdB = 0;
  c.m_triangleIndex = triangleIndex;
  bool onEdge[3];
  locate(tri, onMesh, 0, c.m_barycentric, onEdge);
  clampWeights(c.m_barycentric);
  gatherer.add(c);
}

// The face contact: the shape's face (or deepest point) along -normal inside the
// triangle's side planes, measured to the face plane.
void faceContact(const Triangle& tri, PfxUInt32 triangleIndex, const PfxConvexCore& core,
                 PfxFloat threshold, Gatherer& gatherer) {
  PfxVector3 face[PFX_MAX_SUPPORTING_FACE_POINTS];
  PfxVector3 faceNormal;
  const PfxVector3 down = -tri.normal;
  PfxUInt32 count = core.supportingFace(down, face, faceNormal);
  if (count == 0) {
    face[0] = core.support(down) + down * core.m_radius;
    count = 1;
  }
  PfxVector3 bufferA[PFX_MAX_CLIP_VERTICES];
  PfxVector3 bufferB[PFX_MAX_CLIP_VERTICES];
  PfxVector3* polygon = bufferA;
  PfxVector3* scratch = bufferB;
  std::copy(face, face + count, polygon);
  for (int i = 0; i < 3 && count > 0; ++i) {
    const PfxVector3 side = (tri.v[(i + 1) % 3] - tri.v[i]).cross(tri.normal);
    count = pfxClipPolygonByPlane(polygon, count, side, side.dot(tri.v[i]), scratch,
                                  PFX_MAX_CLIP_VERTICES);
    std::swap(polygon, scratch);
  }
  for (PfxUInt32 k = 0; k < count; ++k) {
    const PfxFloat distance = tri.normal.dot(polygon[k] - tri.v[0]);
    if (!(distance < threshold)) continue;
    addCandidate(gatherer, tri, triangleIndex, tri.normal, polygon[k] - tri.normal * distance,
                 polygon[k], distance);
  }
}

PfxFloat distanceToSegment(const PfxVector3& p, const PfxVector3& a, const PfxVector3& b) {
  const PfxVector3 ab = b - a;
  const PfxFloat lengthSq = ab.squaredNorm();
  const PfxFloat t =
      lengthSq > 0 ? std::clamp((p - a).dot(ab) / lengthSq, PfxFloat(0), PfxFloat(1)) : 0;
  return (a + ab * t - p).norm();
}

void contactTriangle(const Triangle& tri, PfxUInt32 triangleIndex, PfxFloat thickness,
                     const PfxShape& convexShape, const PfxTransform3& convexTransform,
                     const PfxConvexCore& core, PfxFloat threshold, Gatherer& gatherer) {
  // The prism's pair routine (GJK/EPA or separating axes) was most of the cost of a robot
  // on a mesh: a quadruped on a 3,200-triangle terrain spent ten times as long in
  // collision detection as on the terrain's bounding box. Two cases need no prism:
  // - the shape lies wholly above the face plane by the threshold or more, so it is at
  //   least that far from the prism, whose top is that plane;
  const PfxFloat lowest = tri.normal.dot(core.support(-tri.normal) - tri.v[0]) - core.m_radius;
  if (!(lowest < threshold)) return;
  // - every edge is internal or out of the shape's reach, so no prism normal would be kept
  //   (only a point on an edge that may stand out keeps one): the result is the face
  //   contact, or nothing for a shape wholly beneath the prism. This also spares a huge
  //   triangle under a small shape (a ground of two 100 m triangles) GJK and EPA on a
  //   prism a hundred metres across, whose tolerances reported a cylinder 10 cm deeper
  //   than it was.
  const PfxFloat reach = core.boundingRadius() + std::max(threshold, PfxFloat(0)) +
                         PfxFloat(1e-4) * std::max({tri.edgeLength[0], tri.edgeLength[1],
                                                    tri.edgeLength[2]}) +
                         PfxFloat(1e-6);
  bool faceDecides = true;
  for (int i = 0; i < 3 && faceDecides; ++i) {
    if (tri.flags & (PFX_LARGE_MESH_EDGE_INTERNAL_0 << i)) continue;
    faceDecides = distanceToSegment(core.m_position, tri.v[i], tri.v[(i + 1) % 3]) > reach;
  }
  if (faceDecides) {
    const PfxFloat highest = tri.normal.dot(core.support(tri.normal) - tri.v[0]) + core.m_radius;
    if (highest < -thickness) return;
    faceContact(tri, triangleIndex, core, threshold, gatherer);
    return;
  }
  PfxConvexMesh prism;
  buildPrism(tri, thickness, prism);
  PfxShape prismShape;
  prismShape.reset();
  prismShape.setConvexMesh(&prism);
  PfxContactCandidate found[PFX_MAX_CONTACT_CANDIDATES];
  const PfxUInt32 numFound =
      pfxContactConvexShapes(prismShape, PfxTransform3::Identity(), convexShape, convexTransform,
                             threshold, found, PFX_MAX_CONTACT_CANDIDATES);
  if (numFound == 0) return;

  // The pair routines give one normal for all their points.
  const PfxFloat cosine = found[0].m_normal.dot(tri.normal);
  // Separated from the prism with a normal pointing below the face: the shape lies beyond
  // the prism's bottom, beneath the mesh. It is close only to the back of this triangle,
  // e.g. to the far side of a thin closed solid it rests on, and the face contact would
  // pull it through that solid.
  if (cosine < 0) {
    PfxFloat nearest = found[0].m_distance;
    for (PfxUInt32 k = 1; k < numFound; ++k) nearest = std::min(nearest, found[k].m_distance);
    if (nearest > 0) return;
  }
  bool useFace = false;
  if (cosine < kFaceNormalCosine) {
    useFace = true;
    const PfxFloat longest = std::max({tri.edgeLength[0], tri.edgeLength[1], tri.edgeLength[2]});
    const PfxFloat tolerance = PfxFloat(1e-4) * longest + PfxFloat(1e-6);
    // Only a point on an edge that may stand out (a border or a convex fold) keeps the
    // prism's own normal, and only while that normal does not point below the face.
    for (PfxUInt32 k = 0; k < numFound && cosine >= 0; ++k) {
      PfxFloat weights[3];
      bool onEdge[3];
      locate(tri, found[k].m_pointA, tolerance, weights, onEdge);
      for (int i = 0; i < 3; ++i) {
        if (onEdge[i] && !(tri.flags & (PFX_LARGE_MESH_EDGE_INTERNAL_0 << i))) useFace = false;
      }
    }
  }
  if (useFace) {
    faceContact(tri, triangleIndex, core, threshold, gatherer);
    return;
  }
  for (PfxUInt32 k = 0; k < numFound; ++k) {
    // The mesh's point moves along the face normal onto the face plane: the points of a
    // side face move along that face, which leaves their distance along its normal as it
    // was, and the point can then be carried by corner weights.
    const PfxVector3& p = found[k].m_pointA;
    const PfxVector3 onFace = p - tri.normal * tri.normal.dot(p - tri.v[0]);
    addCandidate(gatherer, tri, triangleIndex, found[k].m_normal, onFace, found[k].m_pointB,
                 found[k].m_distance);
  }
}

}  // namespace

void pfxContactLargeMesh(const PfxShape& meshShape, const PfxTransform3& meshTransform,
                         const PfxShape& convexShape, const PfxTransform3& convexTransform,
                         PfxContactSink& sink) {
  const PfxLargeTriMesh* mesh = meshShape.getLargeTriMesh();
  if (!mesh || mesh->m_numNodes == 0) return;
  const PfxFloat threshold = sink.getThreshold();

  // The shape's bounds in the mesh's frame, from its support points along the mesh's axes.
  const PfxTransform3 toMesh = meshTransform.inverse(Eigen::Isometry);
  PfxConvexCore localCore;
  localCore.set(convexShape, toMesh * convexTransform);
  PfxVector3 lo, hi;
  for (int i = 0; i < 3; ++i) {
    const PfxVector3 axis = PfxVector3::Unit(i);
    lo[i] = localCore.support(-axis)[i] - localCore.m_radius - threshold;
    hi[i] = localCore.support(axis)[i] + localCore.m_radius + threshold;
  }
  // The prisms reach below the faces: a face up to `thickness` beyond the box still counts.
  lo -= PfxVector3::Constant(mesh->m_thickness);
  hi += PfxVector3::Constant(mesh->m_thickness);

  PfxConvexCore core;
  core.set(convexShape, convexTransform);
  const PfxFloat thickness = std::max(mesh->m_thickness, kMinPrismThickness);
  Gatherer gatherer;
  pfxQueryLargeTriMesh(*mesh, lo, hi, [&](const PfxLargeMeshIsland& island, PfxUInt32 t) {
    PfxUInt32 corners[3];
    pfxLargeMeshCorners(*mesh, island, t, corners);
    Triangle tri;
    for (int k = 0; k < 3; ++k) tri.v[k] = meshTransform * pfxLargeMeshVertex(*mesh, corners[k]);
    const PfxVector3 cross = (tri.v[1] - tri.v[0]).cross(tri.v[2] - tri.v[0]);
    tri.areaTwice = cross.norm();
    // Quantization can flatten a sliver; it has no face to collide with.
    if (!(tri.areaTwice > 0)) return;
    tri.normal = cross / tri.areaTwice;
    for (int i = 0; i < 3; ++i) tri.edgeLength[i] = (tri.v[(i + 1) % 3] - tri.v[i]).norm();
    tri.flags = mesh->m_edgeFlags[t];
    contactTriangle(tri, t, thickness, convexShape, convexTransform, core, threshold, gatherer);
  });
  gatherer.reduce();
  for (PfxUInt32 i = 0; i < gatherer.m_count; ++i) {
    const PfxContactCandidate& c = gatherer.m_items[i];
    sink.setTriangle(c.m_triangleIndex, c.m_barycentric);
    sink.add(c.m_normal, c.m_pointA, c.m_pointB, c.m_distance);
  }
  sink.clearTriangle();
}

}  // namespace pfx
