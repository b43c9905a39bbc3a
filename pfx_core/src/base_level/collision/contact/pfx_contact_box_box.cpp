// Two boxes by their 15 separating axes in closed form. The answer is the one the general
// polyhedra routine gives (same axis preferences, same face clipping); boxes are the most
// common pair of a stacked scene, and here their faces are axis-aligned in the reference
// box's frame, so the projections are three products and the clipping four comparisons,
// where the general routine builds both polyhedra and walks 144 edge pairs.
#include <algorithm>
#include <cmath>
#include <limits>

#include "base_level/collision/contact/pfx_clip_polygon.h"
#include "base_level/collision/contact/pfx_closest_points.h"
#include "base_level/collision/contact/pfx_contact_pairs.h"
#include "base_level/collision/contact/pfx_gjk.h"

namespace pfx {

namespace {

struct BoxPose {
  PfxVector3 half;
  const PfxTransform3* transform;
};

// A face axis: `axis` of the box it belongs to, its normal pointing at the other box
// (`sign`), and how far the boxes are apart along it.
struct FaceAxis {
  PfxFloat separation = -std::numeric_limits<PfxFloat>::max();
  int axis = 0;
  PfxFloat sign = 1;
};

struct EdgeAxis {
  PfxFloat separation = -std::numeric_limits<PfxFloat>::max();
  int axisA = 0;
  int axisB = 0;
  PfxVector3 normal = PfxVector3::Zero();  // in A's frame, from A to B
  bool found = false;
};

PfxFloat boxAxisSign(PfxFloat x) { return x < 0 ? PfxFloat(-1) : PfxFloat(1); }

// The face axes of a box whose centre sees the other box's centre at `toOther` (in its own
// frame); `otherReach` is how far the other box reaches along each of the box's axes.
FaceAxis bestFaceAxis(const PfxVector3& half, const PfxVector3& toOther,
                      const PfxVector3& otherReach, PfxFloat threshold) {
  FaceAxis best;
  for (int i = 0; i < 3; ++i) {
    const PfxFloat separation = std::abs(toOther[i]) - half[i] - otherReach[i];
    if (separation > best.separation) {
      best.separation = separation;
      best.axis = i;
      best.sign = boxAxisSign(toOther[i]);
      if (separation > threshold) break;
    }
  }
  return best;
}

// rotation: B's axes in A's frame (columns); translation: B's centre in A's frame.
EdgeAxis bestEdgeAxis(const PfxVector3& halfA, const PfxVector3& halfB, const PfxMatrix3& rotation,
                      const PfxVector3& translation, PfxFloat threshold) {
  EdgeAxis best;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      PfxVector3 normal = PfxVector3::Unit(i).cross(rotation.col(j));
      const PfxFloat lengthSq = normal.squaredNorm();
      // Parallel edges: their plane is a face direction, already tested.
      if (lengthSq <= PfxFloat(1e-8)) continue;
      normal /= std::sqrt(lengthSq);
      const PfxFloat centreDistance = normal.dot(translation);
      if (centreDistance < 0) normal = -normal;
      const PfxFloat reachA = halfA.dot(normal.cwiseAbs());
      const PfxFloat reachB = halfB.dot((rotation.transpose() * normal).cwiseAbs());
      const PfxFloat separation = std::abs(centreDistance) - reachA - reachB;
      if (separation > best.separation) {
        best.separation = separation;
        best.axisA = i;
        best.axisB = j;
        best.normal = normal;
        best.found = true;
        if (separation > threshold) return best;
      }
    }
  }
  return best;
}

class BoxBoxContact {
 public:
  BoxBoxContact(const BoxPose& a, const BoxPose& b, PfxContactSink& sink)
      : m_a(a), m_b(b), m_sink(sink) {}

  void run() {
    const PfxTransform3& ta = *m_a.transform;
    const PfxTransform3& tb = *m_b.transform;
    const PfxMatrix3 rotation = ta.linear().transpose() * tb.linear();
    const PfxVector3 translation =
        ta.linear().transpose() * (tb.translation() - ta.translation());
    const PfxMatrix3 absRotation = rotation.cwiseAbs();

    const PfxFloat threshold = m_sink.getThreshold();
    const FaceAxis faceA = bestFaceAxis(m_a.half, translation, absRotation * m_b.half, threshold);
    if (faceA.separation >= threshold) return;
    const FaceAxis faceB = bestFaceAxis(m_b.half, -(rotation.transpose() * translation),
                                        absRotation.transpose() * m_a.half, threshold);
    if (faceB.separation >= threshold) return;
    const EdgeAxis edge = bestEdgeAxis(m_a.half, m_b.half, rotation, translation, threshold);
    if (edge.found && edge.separation >= threshold) return;

    const PfxFloat bestFace = std::max(faceA.separation, faceB.separation);
    const PfxFloat separation = edge.found ? std::max(bestFace, edge.separation) : bestFace;
    // Apart, the closest points as pfxContactPolyhedra finds them (see there why).
    PfxCoreGap gap;
    const bool apart = separation > 0 && pfxGjkGap(core(m_a), core(m_b), gap);
    if (apart && gap.distance >= threshold) return;

    const PfxFloat faceTolerance =
        PfxFloat(1e-3) * std::min(m_a.half.maxCoeff(), m_b.half.maxCoeff()) + PfxFloat(1e-5);
    m_mergeDistance = PfxFloat(1e-2) * faceTolerance;
    // Faces are preferred within a tolerance of the best axis: they give full manifolds for
    // resting contact, and an edge pair that only ties a face adds nothing but jitter.
    const bool faceAQualifies = faceA.separation + faceTolerance >= separation;
    const bool faceBQualifies = faceB.separation + faceTolerance >= separation;
    if (!faceAQualifies && !faceBQualifies && edge.found &&
        edgeContact(edge, rotation, translation)) {
      return;
    }
    bool referenceIsA = faceA.separation >= faceB.separation;
    if (faceAQualifies && faceBQualifies) {
      // A tie: the larger face is the reference, so that the smaller one is clipped to it.
      referenceIsA = faceArea(m_a.half, faceA.axis) >= faceArea(m_b.half, faceB.axis);
    }
    const PfxFloat nearest =
        referenceIsA ? faceContact(m_a, faceA, m_b, true, apart, separation)
                     : faceContact(m_b, faceB, m_a, false, apart, separation);
    // The closest points join unless the face reaches as close, as in pfxContactPolyhedra.
    if (apart && nearest > gap.distance + m_mergeDistance) {
      m_sink.add(gap.normal, gap.pointA, gap.pointB, gap.distance);
    }
  }

 private:
  static PfxConvexCore core(const BoxPose& box) {
    PfxConvexCore c;
    c.m_type = kPfxShapeBox;
    c.m_size = box.half;
    c.m_mesh = nullptr;
    c.m_radius = 0;
    c.m_rotation = box.transform->linear();
    c.m_position = box.transform->translation();
    return c;
  }

  static PfxFloat faceArea(const PfxVector3& half, int axis) {
    return half[(axis + 1) % 3] * half[(axis + 2) % 3];
  }

  // Clips the face of `incident` that most opposes the reference face to the reference
  // face's rectangle; every clipped point within the threshold is a contact, its distance
  // never below `leastDistance`, the separation along the best axis (see
  // pfxContactPolyhedra). Works in the reference box's frame, where the rectangle's sides are
  // axis planes. Returns the nearest distance reported (the largest float when none); for
  // boxes `apart`, as pfxContactPolyhedra does, nothing stands for a face clipped away
  // entirely.
  PfxFloat faceContact(const BoxPose& reference, const FaceAxis& face, const BoxPose& incident,
                       bool referenceIsA, bool apart, PfxFloat leastDistance) {
    const PfxTransform3& refTransform = *reference.transform;
    const PfxMatrix3 rotation = refTransform.linear().transpose() * incident.transform->linear();
    const PfxVector3 centre = refTransform.linear().transpose() *
                              (incident.transform->translation() - refTransform.translation());
    const int k = face.axis;
    const PfxVector3 normal = PfxVector3::Unit(k) * face.sign;

    int incAxis = 0;
    for (int m = 1; m < 3; ++m) {
      if (std::abs(rotation(k, m)) > std::abs(rotation(k, incAxis))) incAxis = m;
    }
    const PfxFloat towardsReference = -boxAxisSign(face.sign * rotation(k, incAxis));
    const PfxVector3 faceCentre =
        centre + rotation.col(incAxis) * (towardsReference * incident.half[incAxis]);
    const int u = (incAxis + 1) % 3;
    const int v = (incAxis + 2) % 3;
    const PfxVector3 edgeU = rotation.col(u) * incident.half[u];
    const PfxVector3 edgeV = rotation.col(v) * incident.half[v];

    PfxVector3 bufferA[PFX_MAX_CLIP_VERTICES];
    PfxVector3 bufferB[PFX_MAX_CLIP_VERTICES];
    PfxVector3* polygon = bufferA;
    PfxVector3* scratch = bufferB;
    const PfxVector3 corners[4] = {faceCentre + edgeU + edgeV, faceCentre - edgeU + edgeV,
                                   faceCentre - edgeU - edgeV, faceCentre + edgeU - edgeV};
    std::copy(corners, corners + 4, polygon);
    PfxUInt32 count = 4;
    for (int side = 1; side < 3 && count > 0; ++side) {
      const int axis = (k + side) % 3;
      for (const PfxFloat direction : {PfxFloat(1), PfxFloat(-1)}) {
        count = pfxClipPolygonByAxisPlane(polygon, count, axis, direction, reference.half[axis],
                                          scratch, PFX_MAX_CLIP_VERTICES);
        std::swap(polygon, scratch);
        if (count == 0) break;
      }
    }

    count = pfxRemoveDuplicatePoints(polygon, count, m_mergeDistance);
    if (count == 0 && !apart) {
      // The boxes touch, yet clipping left nothing of the incident face: the faces meet at
      // most on the reference face's rim (rounding cut the sliver there away). The incident
      // face's point nearest that rim stands for them. The deepest incident corner did
      // before: for nearly parallel faces, a corner up to a box's length beside the
      // reference face, a contact where neither box is.
      const int refU = (k + 1) % 3;
      const int refV = (k + 2) % 3;
      PfxVector3 rim[4];
      const PfxFloat signs[4][2] = {{1, 1}, {-1, 1}, {-1, -1}, {1, -1}};
      for (int i = 0; i < 4; ++i) {
        rim[i][k] = face.sign * reference.half[k];
        rim[i][refU] = signs[i][0] * reference.half[refU];
        rim[i][refV] = signs[i][1] * reference.half[refV];
      }
      polygon[0] = pfxNearestPointAcross(corners, 4, rim, 4, normal, m_mergeDistance);
      count = 1;
    }
    const PfxVector3 worldNormal = refTransform.linear() * normal;
    PfxFloat nearest = std::numeric_limits<PfxFloat>::max();
    for (PfxUInt32 i = 0; i < count; ++i) {
      const PfxVector3& p = polygon[i];
      const PfxFloat distance = std::max(normal.dot(p) - reference.half[k], leastDistance);
      const PfxVector3 onIncident = refTransform * p;
      const PfxVector3 onReference = refTransform * PfxVector3(p - normal * distance);
      if (referenceIsA) {
        m_sink.add(worldNormal, onReference, onIncident, distance);
      } else {
        m_sink.add(-worldNormal, onIncident, onReference, distance);
      }
      nearest = std::min(nearest, distance);
    }
    return nearest;
  }

  // The edge of each box parallel to the axis pair that reaches furthest towards the other
  // box, and their closest points. Returns false when those do not lie on the axis at the
  // separation found (the lines cross beyond an edge's end); a face contact then stands.
  bool edgeContact(const EdgeAxis& edge, const PfxMatrix3& rotation,
                   const PfxVector3& translation) {
    PfxVector3 centreA = PfxVector3::Zero();
    for (int k = 0; k < 3; ++k) {
      if (k != edge.axisA) centreA[k] = m_a.half[k] * boxAxisSign(edge.normal[k]);
    }
    const PfxVector3 alongA = PfxVector3::Unit(edge.axisA) * m_a.half[edge.axisA];

    const PfxVector3 normalInB = rotation.transpose() * edge.normal;
    PfxVector3 centreInB = PfxVector3::Zero();
    for (int k = 0; k < 3; ++k) {
      if (k != edge.axisB) centreInB[k] = -m_b.half[k] * boxAxisSign(normalInB[k]);
    }
    const PfxVector3 centreB = translation + rotation * centreInB;
    const PfxVector3 alongB = rotation.col(edge.axisB) * m_b.half[edge.axisB];

    PfxVector3 onA, onB;
    PfxFloat along;
    if (!pfxEdgeContactPoints(centreA - alongA, centreA + alongA, centreB - alongB,
                              centreB + alongB, edge.normal, edge.separation, m_mergeDistance,
                              onA, onB, along)) {
      return false;
    }
    const PfxTransform3& ta = *m_a.transform;
    m_sink.add(ta.linear() * edge.normal, ta * onA, ta * onB, along);
    return true;
  }

  const BoxPose& m_a;
  const BoxPose& m_b;
  PfxContactSink& m_sink;
  PfxFloat m_mergeDistance = 0;
};

}  // namespace

void pfxContactBoxBox(const PfxVector3& halfA, const PfxTransform3& transformA,
                      const PfxVector3& halfB, const PfxTransform3& transformB,
                      PfxContactSink& sink) {
  const BoxPose a{halfA, &transformA};
  const BoxPose b{halfB, &transformB};
  BoxBoxContact(a, b, sink).run();
}

}  // namespace pfx
