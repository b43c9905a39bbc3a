#include <algorithm>
#include <cmath>

#include "base_level/collision/contact/pfx_closest_points.h"
#include "base_level/collision/contact/pfx_contact_pairs.h"

namespace pfx {

namespace {

// Below this sine of the angle between two capsules they are treated as lying side by side
// and touch along a line, reported by its two ends so that a capsule rests without rocking.
constexpr PfxFloat kParallelSine = PfxFloat(0.01);

// Removes from `v` its component along the unit direction `axis` (when there is one).
PfxVector3 perpendicularTo(const PfxVector3& v, const PfxVector3& axis, bool hasAxis) {
  return hasAxis ? PfxVector3(v - axis * axis.dot(v)) : v;
}

// A direction to push along when the two segments touch, so that no normal is guessed
// from a zero vector. Deterministic: depends only on the segments and A's orientation.
PfxVector3 touchingNormal(const PfxVector3& dirA, bool hasA, const PfxVector3& dirB, bool hasB,
                          const PfxMatrix3& rotationA) {
  if (hasA && hasB) {
    const PfxVector3 c = dirA.cross(dirB);
    if (c.squaredNorm() > kParallelSine * kParallelSine) {
      const PfxVector3 n = c.normalized();
      return n.dot(rotationA.col(1)) < 0 ? PfxVector3(-n) : n;
    }
  }
  for (int column = 1; column <= 2; ++column) {
    PfxVector3 n = perpendicularTo(rotationA.col(column), dirA, hasA);
    n = perpendicularTo(n, dirB, hasB);
    if (n.squaredNorm() > PfxFloat(0.01)) return n.normalized();
  }
  // Only reached when A is a point and B's axis lies along A's +Y: +Z of A is then
  // perpendicular to it.
  return rotationA.col(2);
}

}  // namespace

void pfxContactSweptSpheres(const PfxVector3& a0, const PfxVector3& a1, PfxFloat radiusA,
                            const PfxVector3& b0, const PfxVector3& b1, PfxFloat radiusB,
                            const PfxMatrix3& rotationA, PfxContactSink& sink) {
  PfxFloat s, t;
  PfxVector3 onA, onB;
  pfxClosestPointsSegmentSegment(a0, a1, b0, b1, s, t, onA, onB);
  const PfxVector3 diff = onB - onA;
  const PfxFloat distSq = diff.squaredNorm();
  const PfxFloat radii = radiusA + radiusB;
  const PfxFloat reach = radii + sink.getThreshold();
  if (reach <= 0 || distSq >= reach * reach) return;

  const PfxVector3 edgeA = a1 - a0;
  const PfxVector3 edgeB = b1 - b0;
  const PfxFloat lenA = edgeA.norm();
  const PfxFloat lenB = edgeB.norm();
  const bool hasA = lenA > PFX_EPSILON;
  const bool hasB = lenB > PFX_EPSILON;
  const PfxVector3 dirA = hasA ? PfxVector3(edgeA / lenA) : PfxVector3::Zero();
  const PfxVector3 dirB = hasB ? PfxVector3(edgeB / lenB) : PfxVector3::Zero();

  const PfxFloat dist = std::sqrt(distSq);
  const PfxVector3 normal = dist > PFX_EPSILON ? PfxVector3(diff / dist)
                                               : touchingNormal(dirA, hasA, dirB, hasB, rotationA);

  if (hasA && hasB && dirA.cross(dirB).squaredNorm() < kParallelSine * kParallelSine) {
    // Side by side: the stretch of A that B overlaps, reported by its two ends.
    const PfxFloat tb0 = dirA.dot(b0 - a0) / lenA;
    const PfxFloat tb1 = dirA.dot(b1 - a0) / lenA;
    const PfxFloat lo = std::max(std::min(tb0, tb1), PfxFloat(0));
    const PfxFloat hi = std::min(std::max(tb0, tb1), PfxFloat(1));
    if ((hi - lo) * lenA > PFX_EPSILON) {
      for (const PfxFloat u : {lo, hi}) {
        const PfxVector3 pa = a0 + edgeA * u;
        const PfxVector3 pb = b0 + edgeB * pfxClosestParameterOnSegment(b0, b1, pa);
        sink.add(normal, pa + normal * radiusA, pb - normal * radiusB,
                 normal.dot(pb - pa) - radii);
      }
      return;
    }
  }
  sink.add(normal, onA + normal * radiusA, onB - normal * radiusB, normal.dot(diff) - radii);
}

}  // namespace pfx
