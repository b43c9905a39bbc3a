#include "base_level/collision/contact/pfx_clip_polygon.h"

#include <algorithm>
#include <limits>

#include "base_level/collision/contact/pfx_closest_points.h"

namespace pfx {

namespace {

// The clipping itself, for any signed distance `distanceTo(p)` (above the plane > 0).
template <typename DistanceTo>
PfxUInt32 clipPolygon(const PfxVector3* in, PfxUInt32 numIn, const DistanceTo& distanceTo,
                      PfxVector3* out, PfxUInt32 capacity) {
  if (numIn == 0 || capacity == 0) return 0;
  if (numIn == 1) {
    if (distanceTo(in[0]) > 0) return 0;
    out[0] = in[0];
    return 1;
  }
  // A segment is a polygon whose closing edge is not walked again.
  const PfxUInt32 numEdges = numIn == 2 ? 1 : numIn;
  PfxUInt32 numOut = 0;
  const auto push = [&](const PfxVector3& p) {
    if (numOut < capacity) out[numOut++] = p;
  };
  if (numIn == 2 && distanceTo(in[0]) <= 0) push(in[0]);
  for (PfxUInt32 i = 0; i < numEdges; ++i) {
    const PfxVector3& a = in[i];
    const PfxVector3& b = in[(i + 1) % numIn];
    const PfxFloat da = distanceTo(a);
    const PfxFloat db = distanceTo(b);
    if ((da < 0 && db > 0) || (da > 0 && db < 0)) push(a + (b - a) * (da / (da - db)));
    if (db <= 0) push(b);
  }
  return numOut;
}

}  // namespace

PfxUInt32 pfxClipPolygonByPlane(const PfxVector3* in, PfxUInt32 numIn, const PfxVector3& normal,
                                PfxFloat offset, PfxVector3* out, PfxUInt32 capacity) {
  // A lone point is dropped when the difference is above zero, which for floats is exactly
  // when dot(normal, p) > offset: a difference of floats rounds to zero only when they are equal.
  return clipPolygon(
      in, numIn, [&](const PfxVector3& p) { return normal.dot(p) - offset; }, out, capacity);
}

PfxUInt32 pfxClipPolygonByAxisPlane(const PfxVector3* in, PfxUInt32 numIn, int axis,
                                    PfxFloat direction, PfxFloat offset, PfxVector3* out,
                                    PfxUInt32 capacity) {
  return clipPolygon(
      in, numIn, [&](const PfxVector3& p) { return direction * p[axis] - offset; }, out,
      capacity);
}

}  // namespace pfx

namespace pfx {

namespace {

// How many edges a polygon of `count` points has: a segment one, a point none.
PfxUInt32 edgeCount(PfxUInt32 count) { return count < 3 ? count - (count > 0) : count; }

// Calls visit(point, gap) for each point of `incident` that may come nearest to
// `reference` across `normal`: its vertices, with their distance to the reference's rim,
// and the points of its edges nearest the reference's vertices. Two convex polygons that
// do not overlap come nearest at a vertex of one of them, so one of these is the nearest.
template <typename Visit>
void visitNearCandidates(const PfxVector3* incident, PfxUInt32 numIncident,
                         const PfxVector3* reference, PfxUInt32 numReference,
                         const PfxVector3& normal, const Visit& visit) {
  const auto across = [&](const PfxVector3& p) { return PfxVector3(p - normal * normal.dot(p)); };
  for (PfxUInt32 i = 0; i < numIncident; ++i) {
    const PfxVector3 p = across(incident[i]);
    PfxFloat gap = numReference == 1 ? (across(reference[0]) - p).norm()
                                     : std::numeric_limits<PfxFloat>::max();
    for (PfxUInt32 j = 0; j < edgeCount(numReference); ++j) {
      const PfxVector3 r0 = across(reference[j]);
      const PfxVector3 r1 = across(reference[(j + 1) % numReference]);
      const PfxFloat s = pfxClosestParameterOnSegment(r0, r1, p);
      gap = std::min(gap, PfxFloat((r0 + (r1 - r0) * s - p).norm()));
    }
    visit(incident[i], gap);
  }
  for (PfxUInt32 i = 0; i < edgeCount(numIncident); ++i) {
    const PfxVector3& p0 = incident[i];
    const PfxVector3& p1 = incident[(i + 1) % numIncident];
    for (PfxUInt32 j = 0; j < numReference; ++j) {
      const PfxVector3 r = across(reference[j]);
      const PfxFloat s = pfxClosestParameterOnSegment(across(p0), across(p1), r);
      const PfxVector3 onEdge = p0 + (p1 - p0) * s;
      visit(onEdge, PfxFloat((across(onEdge) - r).norm()));
    }
  }
}

}  // namespace

PfxVector3 pfxNearestPointAcross(const PfxVector3* incident, PfxUInt32 numIncident,
                                 const PfxVector3* reference, PfxUInt32 numReference,
                                 const PfxVector3& normal, PfxFloat tolerance) {
  PfxFloat nearestGap = std::numeric_limits<PfxFloat>::max();
  visitNearCandidates(incident, numIncident, reference, numReference, normal,
                      [&](const PfxVector3&, PfxFloat gap) { nearestGap = std::min(nearestGap, gap); });
  PfxVector3 deepest = incident[0];
  PfxFloat deepestAlong = std::numeric_limits<PfxFloat>::max();
  visitNearCandidates(incident, numIncident, reference, numReference, normal,
                      [&](const PfxVector3& p, PfxFloat gap) {
                        if (gap <= nearestGap + tolerance && normal.dot(p) < deepestAlong) {
                          deepestAlong = normal.dot(p);
                          deepest = p;
                        }
                      });
  return deepest;
}

PfxUInt32 pfxRemoveDuplicatePoints(PfxVector3* points, PfxUInt32 count, PfxFloat tolerance) {
  const PfxFloat toleranceSq = tolerance * tolerance;
  PfxUInt32 kept = 0;
  for (PfxUInt32 i = 0; i < count; ++i) {
    bool duplicate = false;
    for (PfxUInt32 j = 0; j < kept && !duplicate; ++j) {
      duplicate = (points[i] - points[j]).squaredNorm() <= toleranceSq;
    }
    if (!duplicate) points[kept++] = points[i];
  }
  return kept;
}

}  // namespace pfx
