// GJK distance between the cores of two convex shapes (Gilbert, Johnson, Keerthi 1988, with
// the closest-point-on-simplex tests of Ericson, Real-Time Collision Detection, ch. 5/9).
#pragma once

#include "base_level/collision/contact/pfx_convex_core.h"

namespace pfx {

// A point of the Minkowski difference A - B and the two support points it came from.
struct PfxSimplexVertex {
  PfxVector3 w;
  PfxVector3 a;
  PfxVector3 b;
};

struct PfxGjkResult {
  PfxFloat distance;   // between the cores; 0 when they overlap
  PfxVector3 pointA;   // closest points on the cores (world)
  PfxVector3 pointB;
  PfxSimplexVertex simplex[4];  // the last simplex, where EPA starts when they overlap
  PfxUInt32 simplexSize;
  // The search direction (unit, from A to B) along which the cores were seen furthest
  // apart, and that separation: a certain lower bound of their signed distance (negative
  // where no direction showed them apart; minus infinity when the cores overlap at once).
  PfxVector3 separatingNormal;
  PfxFloat separation;
};

// `tolerance` is the distance under which the cores count as touching.
PfxGjkResult pfxGjkDistance(const PfxConvexCore& a, const PfxConvexCore& b, PfxFloat tolerance);

// The closest points of two cores apart by more than `tolerance`, with the unit normal from
// A to B and their distance; false when the cores touch or overlap.
struct PfxCoreGap {
  PfxVector3 normal;
  PfxVector3 pointA;
  PfxVector3 pointB;
  PfxFloat distance;
};
bool pfxGjkGap(const PfxConvexCore& a, const PfxConvexCore& b, PfxFloat tolerance,
               PfxGjkResult& result, PfxCoreGap& gap);
// The same, touching below a hundred-thousandth of the shapes' sizes, as the general pair
// routine counts it.
bool pfxGjkGap(const PfxConvexCore& a, const PfxConvexCore& b, PfxCoreGap& gap);

// The closest point to the origin of the triangle (a, b, c), as barycentric weights.
void pfxClosestToOriginOnTriangle(const PfxVector3& a, const PfxVector3& b, const PfxVector3& c,
                                  PfxFloat weights[3]);

}  // namespace pfx
