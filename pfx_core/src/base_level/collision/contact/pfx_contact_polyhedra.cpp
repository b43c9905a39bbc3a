#include <algorithm>
#include <cmath>
#include <limits>

#include "base_level/collision/contact/pfx_clip_polygon.h"
#include "base_level/collision/contact/pfx_closest_points.h"
#include "base_level/collision/contact/pfx_contact_pairs.h"
#include "base_level/collision/contact/pfx_gjk.h"
#include "base_level/collision/contact/pfx_polyhedron.h"

namespace pfx {

namespace {

// A polyhedron with its vertices, face normals and planes in the frame of shape A.
struct PosedPolyhedron {
  const PfxPolyhedron* topology;
  const PfxVector3* verts;
  const PfxVector3* normals;
  const PfxFloat* planeDist;
  PfxVector3 centroid;

  PfxVector3 faceVertex(PfxUInt32 face, PfxUInt32 k) const {
    return verts[topology->m_faceVertIds[topology->m_faceFirstVert[face] + k]];
  }
  PfxUInt32 faceSize(PfxUInt32 face) const { return topology->m_faceNumVerts[face]; }
  PfxFloat minAlong(const PfxVector3& axis) const {
    PfxFloat lo = std::numeric_limits<PfxFloat>::max();
    for (PfxUInt32 v = 0; v < topology->m_numVerts; ++v) lo = std::min(lo, axis.dot(verts[v]));
    return lo;
  }
  PfxFloat maxAlong(const PfxVector3& axis) const { return -minAlong(-axis); }
  PfxFloat faceArea(PfxUInt32 face) const {
    PfxVector3 sum = PfxVector3::Zero();
    const PfxUInt32 n = faceSize(face);
    const PfxVector3 origin = faceVertex(face, 0);
    for (PfxUInt32 k = 1; k + 1 < n; ++k) {
      sum += (faceVertex(face, k) - origin).cross(faceVertex(face, k + 1) - origin);
    }
    return PfxFloat(0.5) * sum.norm();
  }
};

struct FaceQuery {
  PfxFloat separation = -std::numeric_limits<PfxFloat>::max();
  PfxUInt32 face = 0;
};

struct EdgeQuery {
  PfxFloat separation = -std::numeric_limits<PfxFloat>::max();
  PfxUInt32 edgeA = 0;
  PfxUInt32 edgeB = 0;
  PfxVector3 axis = PfxVector3::Zero();  // from A to B
  bool found = false;
};

// Largest distance of `other` in front of a face plane of `poly`; positive means separated.
FaceQuery queryFaces(const PosedPolyhedron& poly, const PosedPolyhedron& other,
                     PfxFloat threshold) {
  FaceQuery best;
  for (PfxUInt32 f = 0; f < poly.topology->m_numFaces; ++f) {
    const PfxFloat separation = other.minAlong(poly.normals[f]) - poly.planeDist[f];
    if (separation > best.separation) {
      best.separation = separation;
      best.face = f;
      if (separation > threshold) break;
    }
  }
  return best;
}

// Gauss-map test (Gregorius, GDC 2013): two edges can only give a face of the Minkowski
// difference when the arcs of their face normals cross on the unit sphere. a, b are A's
// normals; c, d are B's normals negated.
bool isMinkowskiFace(const PfxVector3& a, const PfxVector3& b, const PfxVector3& c,
                     const PfxVector3& d) {
  const PfxVector3 bxa = b.cross(a);
  const PfxVector3 dxc = d.cross(c);
  const PfxFloat cba = c.dot(bxa);
  const PfxFloat dba = d.dot(bxa);
  const PfxFloat adc = a.dot(dxc);
  const PfxFloat bdc = b.dot(dxc);
  return cba * dba < 0 && adc * bdc < 0 && cba * bdc > 0;
}

EdgeQuery queryEdges(const PosedPolyhedron& a, const PosedPolyhedron& b, PfxFloat threshold) {
  EdgeQuery best;
  const PfxPolyhedron& ta = *a.topology;
  const PfxPolyhedron& tb = *b.topology;
  for (PfxUInt32 i = 0; i < ta.m_numEdges; ++i) {
    const PfxVector3& pa = a.verts[ta.m_edgeVertIds[i][0]];
    const PfxVector3 ea = a.verts[ta.m_edgeVertIds[i][1]] - pa;
    const PfxFloat lenSqA = ea.squaredNorm();
    if (lenSqA <= PFX_EPSILON * PFX_EPSILON) continue;
    const PfxUInt8 fa0 = ta.m_edgeFaces[i][0];
    const PfxUInt8 fa1 = ta.m_edgeFaces[i][1];
    const bool knownA = fa0 != PFX_POLYHEDRON_NO_FACE && fa1 != PFX_POLYHEDRON_NO_FACE;
    for (PfxUInt32 j = 0; j < tb.m_numEdges; ++j) {
      const PfxVector3& pb = b.verts[tb.m_edgeVertIds[j][0]];
      const PfxVector3 eb = b.verts[tb.m_edgeVertIds[j][1]] - pb;
      const PfxFloat lenSqB = eb.squaredNorm();
      if (lenSqB <= PFX_EPSILON * PFX_EPSILON) continue;
      const PfxUInt8 fb0 = tb.m_edgeFaces[j][0];
      const PfxUInt8 fb1 = tb.m_edgeFaces[j][1];
      const bool known = knownA && fb0 != PFX_POLYHEDRON_NO_FACE && fb1 != PFX_POLYHEDRON_NO_FACE;
      if (known && !isMinkowskiFace(a.normals[fa0], a.normals[fa1], -b.normals[fb0],
                                    -b.normals[fb1])) {
        continue;
      }
      PfxVector3 axis = ea.cross(eb);
      const PfxFloat axisLenSq = axis.squaredNorm();
      // Parallel edges: their plane is a face direction, already tested.
      if (axisLenSq <= PfxFloat(1e-8) * lenSqA * lenSqB) continue;
      axis /= std::sqrt(axisLenSq);

      PfxFloat separation;
      const PfxVector3 fromCentroid = pa - a.centroid;
      const PfxFloat side = axis.dot(fromCentroid);
      if (known && side * side > PfxFloat(1e-8) * fromCentroid.squaredNorm()) {
        if (side < 0) axis = -axis;
        separation = axis.dot(pb - pa);
      } else {
        // The edge's faces are unknown or A is flat here: measure both ways by support
        // and keep the better, which is a valid separation either way.
        const PfxFloat forward = b.minAlong(axis) - a.maxAlong(axis);
        const PfxFloat backward = a.minAlong(axis) - b.maxAlong(axis);
        if (backward > forward) axis = -axis;
        separation = std::max(forward, backward);
      }
      if (separation > best.separation) {
        best.separation = separation;
        best.edgeA = i;
        best.edgeB = j;
        best.axis = axis;
        best.found = true;
        if (separation > threshold) return best;
      }
    }
  }
  return best;
}

class PolyhedraContact {
 public:
  PolyhedraContact(const PosedPolyhedron& a, const PosedPolyhedron& b,
                   const PfxTransform3& transformA, PfxContactSink& sink)
      : m_a(a), m_b(b), m_transformA(transformA), m_sink(sink) {}

  // coreA, coreB: the two shapes in the world, for their gap once they are apart.
  void run(PfxFloat faceTolerance, const PfxConvexCore& coreA, const PfxConvexCore& coreB) {
    m_mergeDistance = PfxFloat(1e-2) * faceTolerance;
    const PfxFloat threshold = m_sink.getThreshold();
    const FaceQuery faceA = queryFaces(m_a, m_b, threshold);
    if (faceA.separation >= threshold) return;
    const FaceQuery faceB = queryFaces(m_b, m_a, threshold);
    if (faceB.separation >= threshold) return;
    const EdgeQuery edge = queryEdges(m_a, m_b, threshold);
    if (edge.found && edge.separation >= threshold) return;

    const PfxFloat bestFace = std::max(faceA.separation, faceB.separation);
    const PfxFloat separation = edge.found ? std::max(bestFace, edge.separation) : bestFace;
    // Apart, the best separating axis gives only a lower bound of the gap (exact where a face
    // or an edge pair is closest, short of it where a vertex meets an edge or a vertex), and
    // the faces clipped along it may lie beside the closest points: a gap reported larger
    // than there is, none at all, or a vertex beside the reference face taken for an
    // overlap. GJK's closest points are exact there; they join the clipped face when it does
    // not reach as close.
    PfxCoreGap gap;
    const bool apart = separation > 0 && pfxGjkGap(coreA, coreB, gap);
    if (apart && gap.distance >= threshold) return;

    // Faces are preferred within a tolerance of the best axis: they give full manifolds for
    // resting contact, and an edge pair that only ties a face adds nothing but jitter. The
    // face's points are measured along its normal but never deeper than the best axis's
    // separation, which is the exact depth of the overlap: along a face axis up to the
    // tolerance behind it, the deepest vertex came out that much deeper than the shapes
    // overlap (0.3 mm on boxes of 0.6 m).
    const bool faceAQualifies = faceA.separation + faceTolerance >= separation;
    const bool faceBQualifies = faceB.separation + faceTolerance >= separation;
    if (!faceAQualifies && !faceBQualifies && edge.found && edgeContact(edge)) return;
    bool referenceIsA = faceA.separation >= faceB.separation;
    if (faceAQualifies && faceBQualifies) {
      // A tie: the larger face is the reference, so that the smaller one is clipped to it.
      referenceIsA = m_a.faceArea(faceA.face) >= m_b.faceArea(faceB.face);
    }
    const PfxFloat nearest =
        referenceIsA ? faceContact(m_a, faceA.face, m_b, true, apart, separation)
                     : faceContact(m_b, faceB.face, m_a, false, apart, separation);
    // The face kept within its margin of the best axis can report its nearest point up to
    // that margin further away than the shapes are (a box's face 0.06 mm too far, 10,000
    // poses of seed 7): the closest points join unless the face reaches as close to the
    // merge distance, rounding at these sizes.
    if (apart && nearest > gap.distance + m_mergeDistance) {
      m_sink.add(gap.normal, gap.pointA, gap.pointB, gap.distance);
    }
  }

 private:
  // Clips the face of `incident` that most opposes the reference face against the
  // reference face's side planes; every clipped point within the threshold is a contact,
  // its distance never below `leastDistance`. Returns the nearest distance reported (the
  // largest float when none). For shapes `apart`, a face clipped away entirely has nothing
  // to report: its vertices lie beside the reference face, where their height over its
  // plane is no distance between the shapes.
  PfxFloat faceContact(const PosedPolyhedron& reference, PfxUInt32 refFace,
                       const PosedPolyhedron& incident, bool referenceIsA, bool apart,
                       PfxFloat leastDistance) {
    const PfxVector3 refNormal = reference.normals[refFace];
    const PfxFloat refDist = reference.planeDist[refFace];

    PfxUInt32 incFace = 0;
    PfxFloat minDot = std::numeric_limits<PfxFloat>::max();
    for (PfxUInt32 f = 0; f < incident.topology->m_numFaces; ++f) {
      const PfxFloat d = incident.normals[f].dot(refNormal);
      if (d < minDot) {
        minDot = d;
        incFace = f;
      }
    }

    // A face has no more corners than its mesh.
    PfxVector3 incidentFace[PFX_CONVEX_MESH_MAX_VERTICES];
    PfxVector3 referenceFace[PFX_CONVEX_MESH_MAX_VERTICES];
    const PfxUInt32 incSize = std::min(incident.faceSize(incFace), PFX_CONVEX_MESH_MAX_VERTICES);
    const PfxUInt32 refSize = std::min(reference.faceSize(refFace), PFX_CONVEX_MESH_MAX_VERTICES);
    for (PfxUInt32 k = 0; k < incSize; ++k) incidentFace[k] = incident.faceVertex(incFace, k);
    for (PfxUInt32 k = 0; k < refSize; ++k) referenceFace[k] = reference.faceVertex(refFace, k);

    PfxVector3 bufferA[PFX_MAX_CLIP_VERTICES];
    PfxVector3 bufferB[PFX_MAX_CLIP_VERTICES];
    PfxVector3* polygon = bufferA;
    PfxVector3* scratch = bufferB;
    PfxUInt32 count = incSize;
    std::copy(incidentFace, incidentFace + incSize, polygon);

    PfxVector3 refCentre = PfxVector3::Zero();
    for (PfxUInt32 k = 0; k < refSize; ++k) refCentre += referenceFace[k];
    refCentre /= PfxFloat(std::max<PfxUInt32>(refSize, 1));

    for (PfxUInt32 k = 0; k < refSize && count > 0; ++k) {
      const PfxVector3 v0 = referenceFace[k];
      const PfxVector3 v1 = referenceFace[(k + 1) % refSize];
      PfxVector3 sideNormal = (v1 - v0).cross(refNormal);
      if (sideNormal.squaredNorm() <= PFX_EPSILON * PFX_EPSILON) continue;
      if (sideNormal.dot(refCentre - v0) > 0) sideNormal = -sideNormal;
      count = pfxClipPolygonByPlane(polygon, count, sideNormal, sideNormal.dot(v0), scratch,
                                    PFX_MAX_CLIP_VERTICES);
      std::swap(polygon, scratch);
    }

    count = pfxRemoveDuplicatePoints(polygon, count, m_mergeDistance);
    if (count == 0 && !apart) {
      // The shapes touch, yet clipping left nothing of the incident face: the faces meet at
      // most on the reference face's rim, and the incident face's point nearest that rim
      // stands for them (as in pfxContactBoxBox; its deepest vertex could lie beside the
      // reference face).
      polygon[0] = pfxNearestPointAcross(incidentFace, incSize, referenceFace, refSize,
                                         refNormal, m_mergeDistance);
      count = 1;
    }
    PfxFloat nearest = std::numeric_limits<PfxFloat>::max();
    for (PfxUInt32 k = 0; k < count; ++k) {
      const PfxVector3& p = polygon[k];
      const PfxFloat dist = std::max(refNormal.dot(p) - refDist, leastDistance);
      const PfxVector3 onReference = p - refNormal * dist;
      if (referenceIsA) {
        emit(refNormal, onReference, p, dist);
      } else {
        emit(-refNormal, p, onReference, dist);
      }
      nearest = std::min(nearest, dist);
    }
    return nearest;
  }

  // Returns false when the closest points of the two edges do not lie on the separating
  // axis at the separation found (their lines cross beyond an end), which only flat shapes
  // produce; a face contact then describes the pair.
  bool edgeContact(const EdgeQuery& edge) {
    const PfxPolyhedron& ta = *m_a.topology;
    const PfxPolyhedron& tb = *m_b.topology;
    // Parallel edges share the axis; the ones furthest towards each other touch.
    const PfxUInt32 edgeA = supportingEdge(m_a, edge.edgeA, edge.axis);
    const PfxUInt32 edgeB = supportingEdge(m_b, edge.edgeB, -edge.axis);
    PfxVector3 onA, onB;
    PfxFloat along;
    if (!pfxEdgeContactPoints(m_a.verts[ta.m_edgeVertIds[edgeA][0]],
                              m_a.verts[ta.m_edgeVertIds[edgeA][1]],
                              m_b.verts[tb.m_edgeVertIds[edgeB][0]],
                              m_b.verts[tb.m_edgeVertIds[edgeB][1]], edge.axis, edge.separation,
                              m_mergeDistance, onA, onB, along)) {
      return false;
    }
    emit(edge.axis, onA, onB, along);
    return true;
  }

  // Among the edges of `poly` parallel to edge `found`, the one furthest along `dir`.
  static PfxUInt32 supportingEdge(const PosedPolyhedron& poly, PfxUInt32 found,
                                  const PfxVector3& dir) {
    const PfxPolyhedron& topology = *poly.topology;
    const auto endPoints = [&](PfxUInt32 e, PfxVector3& p0, PfxVector3& p1) {
      p0 = poly.verts[topology.m_edgeVertIds[e][0]];
      p1 = poly.verts[topology.m_edgeVertIds[e][1]];
    };
    PfxVector3 f0, f1;
    endPoints(found, f0, f1);
    const PfxVector3 along = f1 - f0;
    PfxUInt32 best = found;
    PfxFloat bestReach = dir.dot(f0 + f1);
    for (PfxUInt32 e = 0; e < topology.m_numEdges; ++e) {
      PfxVector3 p0, p1;
      endPoints(e, p0, p1);
      const PfxVector3 other = p1 - p0;
      if (other.cross(along).squaredNorm() > PfxFloat(1e-8) * other.squaredNorm() *
                                                 along.squaredNorm()) {
        continue;
      }
      if (dir.dot(p0 + p1) > bestReach) {
        bestReach = dir.dot(p0 + p1);
        best = e;
      }
    }
    return best;
  }

  void emit(const PfxVector3& normal, const PfxVector3& onA, const PfxVector3& onB,
            PfxFloat dist) {
    m_sink.add(m_transformA.linear() * normal, m_transformA * onA, m_transformA * onB, dist);
  }

  const PosedPolyhedron& m_a;
  const PosedPolyhedron& m_b;
  const PfxTransform3& m_transformA;
  PfxContactSink& m_sink;
  PfxFloat m_mergeDistance = 0;
};

PfxFloat shapeSize(const PfxShape& shape) {
  return shape.getType() == kPfxShapeBox ? shape.getBox().m_half.maxCoeff()
                                         : shape.getConvexMesh()->m_aabbHalf.maxCoeff();
}

}  // namespace

void pfxContactPolyhedra(const PfxShape& shapeA, const PfxTransform3& transformA,
                         const PfxShape& shapeB, const PfxTransform3& transformB,
                         PfxContactSink& sink) {
  PfxPolyhedron polyA, polyB;
  polyA.build(shapeA);
  polyB.build(shapeB);

  // Everything is compared in A's frame: B's vertices and planes are moved there once.
  const PfxMatrix3 rotation = transformA.linear().transpose() * transformB.linear();
  const PfxVector3 translation =
      transformA.linear().transpose() * (transformB.translation() - transformA.translation());
  PfxVector3 vertsB[PFX_CONVEX_MESH_MAX_VERTICES];
  PfxVector3 normalsB[PFX_CONVEX_MESH_MAX_FACETS];
  PfxFloat planeDistB[PFX_CONVEX_MESH_MAX_FACETS];
  for (PfxUInt32 v = 0; v < polyB.m_numVerts; ++v) {
    vertsB[v] = rotation * polyB.m_verts[v] + translation;
  }
  for (PfxUInt32 f = 0; f < polyB.m_numFaces; ++f) {
    normalsB[f] = rotation * polyB.m_faceNormals[f];
    planeDistB[f] = polyB.m_facePlaneDist[f] + normalsB[f].dot(translation);
  }

  const PosedPolyhedron a{&polyA, polyA.m_verts, polyA.m_faceNormals, polyA.m_facePlaneDist,
                          polyA.m_centroid};
  const PosedPolyhedron b{&polyB, vertsB, normalsB, planeDistB,
                          rotation * polyB.m_centroid + translation};
  const PfxFloat faceTolerance =
      PfxFloat(1e-3) * std::min(shapeSize(shapeA), shapeSize(shapeB)) + PfxFloat(1e-5);
  PfxConvexCore coreA, coreB;
  coreA.set(shapeA, transformA);
  coreB.set(shapeB, transformB);
  PolyhedraContact(a, b, transformA, sink).run(faceTolerance, coreA, coreB);
}

}  // namespace pfx
