#include <algorithm>
#include <cmath>
#include <limits>

#include "base_level/collision/contact/pfx_clip_polygon.h"
#include "base_level/collision/contact/pfx_contact_pairs.h"
#include "base_level/collision/contact/pfx_convex_core.h"
#include "base_level/collision/contact/pfx_epa.h"
#include "base_level/collision/contact/pfx_gjk.h"

namespace pfx {

namespace {

// Two segment faces (capsule or cylinder sides) give a line contact only when they lie
// within about 11.5 degrees of each other; crossing sides touch in one point.
constexpr PfxFloat kParallelSegmentsCosine = PfxFloat(0.98);
// A reference face seen this obliquely along the contact normal cannot project points.
constexpr PfxFloat kMinProjectionCosine = PfxFloat(0.1);

struct Contact {
  PfxVector3 normal;  // from A to B
  PfxVector3 pointA;
  PfxVector3 pointB;
  PfxFloat distance;
};

// When no polytope can be built (zero-size or flat cores), the least overlap among the
// box axes of both shapes and the line between their centres. Defined for any input.
Contact leastOverlapContact(const PfxConvexCore& a, const PfxConvexCore& b) {
  PfxVector3 axes[7];
  for (int i = 0; i < 3; ++i) {
    axes[i] = a.m_rotation.col(i);
    axes[3 + i] = b.m_rotation.col(i);
  }
  const PfxVector3 centres = b.m_position - a.m_position;
  const PfxFloat centresLen = centres.norm();
  const int numAxes = centresLen > PFX_EPSILON ? 7 : 6;
  if (numAxes == 7) axes[6] = centres / centresLen;

  Contact best;
  best.distance = std::numeric_limits<PfxFloat>::max();
  for (int i = 0; i < numAxes; ++i) {
    for (const PfxFloat sign : {PfxFloat(1), PfxFloat(-1)}) {
      const PfxVector3 n = axes[i] * sign;
      const PfxVector3 onA = a.support(n);
      const PfxVector3 onB = b.support(-n);
      const PfxFloat overlap = n.dot(onA - onB);
      if (-overlap < best.distance) {
        best.distance = -overlap;
        best.normal = n;
        best.pointA = onA;
        best.pointB = onB;
      }
    }
  }
  return best;
}

// Deepest contact of the two shapes (radii included), or false when they are further
// apart than `threshold`.
bool deepestContact(const PfxConvexCore& a, const PfxConvexCore& b, PfxFloat scale,
                    PfxFloat threshold, Contact& contact) {
  const PfxFloat radii = a.m_radius + b.m_radius;
  const PfxFloat touching = PfxFloat(1e-5) * scale;
  PfxGjkResult gjk;
  PfxCoreGap gap;
  const bool apart = pfxGjkGap(a, b, touching, gjk, gap);
  if (gjk.distance - radii >= threshold) return false;

  if (apart) {
    contact.normal = gap.normal;
    contact.pointA = gap.pointA;
    contact.pointB = gap.pointB;
    contact.distance = gap.distance;
  } else {
    PfxEpaResult epa;
    if (pfxEpaPenetration(a, b, gjk.simplex, gjk.simplexSize, PfxFloat(1e-5) * scale, epa)) {
      contact.normal = epa.normal;
      contact.pointA = epa.pointA;
      contact.pointB = epa.pointB;
      contact.distance = -epa.depth;
    } else {
      contact = leastOverlapContact(a, b);
    }
  }
  contact.pointA += contact.normal * a.m_radius;
  contact.pointB -= contact.normal * b.m_radius;
  contact.distance -= radii;
  return contact.distance < threshold;
}

// A face as the clipper sees it: points and the outward normal of its plane.
struct Face {
  PfxVector3 points[PFX_MAX_SUPPORTING_FACE_POINTS];
  PfxUInt32 count;
  PfxVector3 normal;
};

// How far the whole shapes (radii included) overlap along the unit `normal`, from A to B.
PfxFloat overlapAlong(const PfxConvexCore& a, const PfxConvexCore& b, const PfxVector3& normal) {
  return normal.dot(a.support(normal) - b.support(-normal)) + a.m_radius + b.m_radius;
}

// Clips `incident` by the side planes of `reference` (polygon edges, or the end planes of a
// segment) and measures each remaining point along `normal` to the reference plane, but
// never below `leastDistance`, the shapes' overlap along the normal: with the normal tilted
// from the reference face's own (up to 11.5 degrees), a point near the face's rim leaves
// the reference shape through a side face before it reaches the face's plane, and measured
// to the plane it came out up to 3.5 mm deeper than the shapes overlap at all.
// Writes contacts in A-to-B order; returns how many.
PfxUInt32 clipFaces(const Face& reference, const Face& incident, bool referenceIsA,
                    const PfxVector3& normal, PfxFloat leastDistance, PfxFloat mergeDistance,
                    Contact* out) {
  const PfxFloat projection = reference.normal.dot(referenceIsA ? normal : PfxVector3(-normal));
  if (projection < kMinProjectionCosine) return 0;

  PfxVector3 bufferA[PFX_MAX_CLIP_VERTICES];
  PfxVector3 bufferB[PFX_MAX_CLIP_VERTICES];
  PfxVector3* polygon = bufferA;
  PfxVector3* scratch = bufferB;
  PfxUInt32 count = incident.count;
  std::copy(incident.points, incident.points + count, polygon);

  const auto clip = [&](const PfxVector3& planeNormal, PfxFloat offset) {
    count = pfxClipPolygonByPlane(polygon, count, planeNormal, offset, scratch,
                                  PFX_MAX_CLIP_VERTICES);
    std::swap(polygon, scratch);
  };
  if (reference.count == 2) {
    const PfxVector3 along = reference.points[1] - reference.points[0];
    clip(-along, -along.dot(reference.points[0]));
    clip(along, along.dot(reference.points[1]));
  } else {
    PfxVector3 centre = PfxVector3::Zero();
    for (PfxUInt32 k = 0; k < reference.count; ++k) centre += reference.points[k];
    centre /= PfxFloat(reference.count);
    for (PfxUInt32 k = 0; k < reference.count && count > 0; ++k) {
      const PfxVector3& v0 = reference.points[k];
      const PfxVector3& v1 = reference.points[(k + 1) % reference.count];
      PfxVector3 side = (v1 - v0).cross(reference.normal);
      if (side.squaredNorm() <= PFX_EPSILON * PFX_EPSILON) continue;
      if (side.dot(centre - v0) > 0) side = -side;
      clip(side, side.dot(v0));
    }
  }

  count = pfxRemoveDuplicatePoints(polygon, count, mergeDistance);
  const PfxVector3& origin = reference.points[0];
  const PfxFloat along = reference.normal.dot(normal);
  for (PfxUInt32 k = 0; k < count; ++k) {
    const PfxVector3& p = polygon[k];
    // The point of the reference plane reached from p along the contact normal.
    const PfxFloat s = reference.normal.dot(origin - p) / along;
    const PfxFloat distance = std::max(referenceIsA ? -s : s, leastDistance);
    Contact& c = out[k];
    c.normal = normal;
    c.distance = distance;
    if (referenceIsA) {
      c.pointA = p - normal * distance;
      c.pointB = p;
    } else {
      c.pointA = p;
      c.pointB = p + normal * distance;
    }
  }
  return count;
}

// EPA's normal on a curved surface is off by about the square root of its depth error,
// a few milliradians. Near a flat face, or between two parallel side lines, the exact
// normal is known from the features themselves; within this cosine of it, it replaces
// EPA's.
constexpr PfxFloat kSnapCosine = PfxFloat(0.9998);

bool segmentsParallel(const Face& faceA, const Face& faceB) {
  if (faceA.count != 2 || faceB.count != 2) return true;
  const PfxVector3 dirA = (faceA.points[1] - faceA.points[0]).normalized();
  const PfxVector3 dirB = (faceB.points[1] - faceB.points[0]).normalized();
  return std::abs(dirA.dot(dirB)) >= kParallelSegmentsCosine;
}

// The faces both shapes present along `normal`; false when they cannot be clipped.
bool supportingFaces(const PfxConvexCore& a, const PfxConvexCore& b, const PfxVector3& normal,
                     Face& faceA, Face& faceB) {
  faceA.count = a.supportingFace(normal, faceA.points, faceA.normal);
  faceB.count = b.supportingFace(-normal, faceB.points, faceB.normal);
  return faceA.count >= 2 && faceB.count >= 2 && segmentsParallel(faceA, faceB);
}

// A line through a segment face that does not depend on the direction it was found along:
// a capsule's or cylinder's axis, or else the face itself (a flat box's side).
void faceLine(const PfxConvexCore& core, const Face& face, PfxVector3& point, PfxVector3& dir) {
  if (core.m_type == kPfxShapeCapsule || core.m_type == kPfxShapeCylinder) {
    point = core.m_position;
    dir = core.m_rotation.col(0);
  } else {
    point = face.points[0];
    dir = (face.points[1] - face.points[0]).normalized();
  }
}

PfxVector3 snappedNormal(const PfxConvexCore& a, const PfxConvexCore& b, const Face& faceA,
                         const Face& faceB, const PfxVector3& normal) {
  PfxVector3 best = normal;
  PfxFloat bestCos = kSnapCosine;
  if (faceA.count >= 3 && faceA.normal.dot(normal) > bestCos) {
    best = faceA.normal;
    bestCos = faceA.normal.dot(normal);
  }
  if (faceB.count >= 3 && -faceB.normal.dot(normal) > bestCos) {
    best = -faceB.normal;
    bestCos = -faceB.normal.dot(normal);
  }
  if (faceA.count == 2 && faceB.count == 2) {
    PfxVector3 pointA, dirA, pointB, dirB;
    faceLine(a, faceA, pointA, dirA);
    faceLine(b, faceB, pointB, dirB);
    const PfxVector3 between = pointB - pointA;
    const PfxVector3 across = between - dirA * dirA.dot(between);
    const PfxFloat len = across.norm();
    if (len > PFX_EPSILON && across.dot(normal) > bestCos * len) best = across / len;
  }
  return best;
}

// A box many times the size of the other shape (a ground slab under a wheel) is cut down,
// in its own frame, to a cube around the other shape: an exact stand-in near it, as every
// face there is the box's own. GJK and EPA on the full slab work on a Minkowski difference
// tens of metres across with tolerances to match: a lying cylinder on a 100 m slab got no
// contact 2 cm deep, and a step later one 50 m deep along a far side face. The cube's cut
// faces lie further out than the nearest real face by the other shape's bounding radius
// and more, so the way out through a real face is always the shorter one. Returns false
// when the other shape cannot reach the box.
constexpr PfxFloat kLargeBoxRatio = 4;

bool cropLargeBox(PfxConvexCore& box, const PfxConvexCore& other, PfxFloat threshold) {
  if (box.m_type != kPfxShapeBox) return true;
  const PfxFloat otherRadius = other.boundingRadius();
  if (box.boundingRadius() <= kLargeBoxRatio * otherRadius) return true;
  const PfxVector3 centre = box.m_rotation.transpose() * (other.m_position - box.m_position);
  const PfxFloat nearestFace = (box.m_size - centre.cwiseAbs()).minCoeff();
  const PfxFloat reach =
      2 * otherRadius + std::max(threshold, PfxFloat(0)) + std::max(nearestFace, PfxFloat(0));
  const PfxVector3 lower = (centre.array() - reach).max(-box.m_size.array()).matrix();
  const PfxVector3 upper = (centre.array() + reach).min(box.m_size.array()).matrix();
  if ((upper.array() < lower.array()).any()) return false;
  box.m_size = (upper - lower) / 2;
  box.m_position += box.m_rotation * ((upper + lower) / 2);
  return true;
}

}  // namespace

void pfxContactConvexGeneral(const PfxShape& shapeA, const PfxTransform3& transformA,
                             const PfxShape& shapeB, const PfxTransform3& transformB,
                             PfxContactSink& sink) {
  PfxConvexCore a, b;
  a.set(shapeA, transformA);
  b.set(shapeB, transformB);
  const PfxFloat threshold = sink.getThreshold();
  if (!cropLargeBox(a, b, threshold) || !cropLargeBox(b, a, threshold)) return;
  const PfxFloat scale = a.boundingRadius() + b.boundingRadius() + PFX_EPSILON;

  Contact deepest;
  if (!deepestContact(a, b, scale, threshold, deepest)) return;
  // Where both shapes present a face (or a side line) to each other, the clipped faces
  // give the whole contact area (the approach of Jolt Physics' manifold builder).
  PfxVector3 normal = deepest.normal;
  Face faceA, faceB;
  bool useFaces = supportingFaces(a, b, normal, faceA, faceB);
  if (useFaces) {
    // A snapped normal must not need a longer push apart than the one it replaces: a face
    // within the snapping angle of a capsule's or cylinder's contact is not always the one
    // it rests on (a capsule across a mesh face's edge took 8.7 mm more along the face's).
    const PfxVector3 snapped = snappedNormal(a, b, faceA, faceB, normal);
    if (snapped != normal && overlapAlong(a, b, snapped) <=
                                 overlapAlong(a, b, normal) + PfxFloat(1e-5) * scale) {
      normal = snapped;
      useFaces = supportingFaces(a, b, normal, faceA, faceB);
    }
  }
  Contact clipped[PFX_MAX_CLIP_VERTICES];
  PfxUInt32 numClipped = 0;
  if (useFaces) {
    const bool referenceIsA = faceA.count >= 3 || faceB.count == 2;
    const PfxFloat mergeDistance = PfxFloat(1e-6) * scale;
    const PfxFloat leastDistance = -overlapAlong(a, b, normal);
    numClipped = referenceIsA
                     ? clipFaces(faceA, faceB, true, normal, leastDistance, mergeDistance, clipped)
                     : clipFaces(faceB, faceA, false, normal, leastDistance, mergeDistance, clipped);
  }

  PfxUInt32 numInside = 0;
  PfxFloat deepestClipped = std::numeric_limits<PfxFloat>::max();
  for (PfxUInt32 k = 0; k < numClipped; ++k) {
    if (clipped[k].distance < threshold) {
      ++numInside;
      deepestClipped = std::min(deepestClipped, clipped[k].distance);
    }
  }
  if (numInside >= 2) {
    for (PfxUInt32 k = 0; k < numClipped; ++k) {
      sink.add(clipped[k].normal, clipped[k].pointA, clipped[k].pointB, clipped[k].distance);
    }
  }
  // The deepest point joins unless the face contacts already reach as deep, to GJK's and
  // EPA's own tolerance: polygons that stand in for curved rims can miss the true deepest
  // point by a few millimetres (with a millimetre's slack a capsule or cylinder 14 mm from
  // a mesh face was reported 0.3 mm further away than it is), and so can a side clipped at
  // a face's edge where the shapes come closest just beyond it. With a slack of 1e-4 of the
  // shapes' size a cylinder's cap 0.020 m from a capsule's side, and a capsule's side
  // 0.85 mm from a mesh face, were reported 6.4e-5 and 9.4e-5 m further apart than they are.
  if (numInside < 2 || deepestClipped > deepest.distance + PfxFloat(1e-5) * scale) {
    sink.add(deepest.normal, deepest.pointA, deepest.pointB, deepest.distance);
  }
}

}  // namespace pfx
