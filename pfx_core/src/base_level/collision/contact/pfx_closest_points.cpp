#include "base_level/collision/contact/pfx_closest_points.h"

#include <algorithm>
#include <cmath>

namespace pfx {

namespace {

PfxFloat clamp01(PfxFloat x) { return std::min(std::max(x, PfxFloat(0)), PfxFloat(1)); }

}  // namespace

PfxFloat pfxClosestParameterOnSegment(const PfxVector3& p0, const PfxVector3& p1,
                                      const PfxVector3& point) {
  const PfxVector3 d = p1 - p0;
  const PfxFloat dd = d.squaredNorm();
  if (dd <= PFX_EPSILON * PFX_EPSILON) return 0;
  return clamp01(d.dot(point - p0) / dd);
}

void pfxClosestPointsSegmentSegment(const PfxVector3& p0, const PfxVector3& p1,
                                    const PfxVector3& q0, const PfxVector3& q1, PfxFloat& s,
                                    PfxFloat& t, PfxVector3& onP, PfxVector3& onQ) {
  // Minimises |p(s) - q(t)|^2 over the unit square: the unconstrained s for the line of Q,
  // clamped, then t for that s, clamped, then s again for a clamped t.
  const PfxVector3 d1 = p1 - p0;
  const PfxVector3 d2 = q1 - q0;
  const PfxVector3 r = p0 - q0;
  const PfxFloat a = d1.squaredNorm();
  const PfxFloat e = d2.squaredNorm();
  const PfxFloat f = d2.dot(r);
  const PfxFloat tiny = PFX_EPSILON * PFX_EPSILON;

  if (a <= tiny && e <= tiny) {
    s = t = 0;
  } else if (a <= tiny) {
    s = 0;
    t = clamp01(f / e);
  } else {
    const PfxFloat c = d1.dot(r);
    if (e <= tiny) {
      t = 0;
      s = clamp01(-c / a);
    } else {
      const PfxFloat b = d1.dot(d2);
      const PfxFloat denom = a * e - b * b;
      // Relative test: denom is |d1|^2 |d2|^2 sin^2 of the angle between them.
      s = denom > PfxFloat(1e-10) * a * e ? clamp01((b * f - c * e) / denom) : PfxFloat(0);
      t = (b * s + f) / e;
      if (t < 0) {
        t = 0;
        s = clamp01(-c / a);
      } else if (t > 1) {
        t = 1;
        s = clamp01((b - c) / a);
      }
    }
  }
  onP = p0 + d1 * s;
  onQ = q0 + d2 * t;
}

bool pfxEdgeContactPoints(const PfxVector3& p0, const PfxVector3& p1, const PfxVector3& q0,
                          const PfxVector3& q1, const PfxVector3& axis, PfxFloat separation,
                          PfxFloat mergeDistance, PfxVector3& onP, PfxVector3& onQ,
                          PfxFloat& distance) {
  PfxFloat s, t;
  pfxClosestPointsSegmentSegment(p0, p1, q0, q1, s, t, onP, onQ);
  const PfxVector3 gap = onQ - onP;
  distance = axis.dot(gap);
  const PfxFloat tolerance = mergeDistance + PfxFloat(1e-4) * std::abs(separation);
  return (gap - axis * distance).norm() <= tolerance &&
         std::abs(distance - separation) <= tolerance;
}

}  // namespace pfx
