// Closest points between the simple pieces that the pair routines are made of.
#pragma once

#include "pfx/base_level/base/pfx_vec_math.h"

namespace pfx {

// Closest points between segments p0-p1 and q0-q1: onP = p0 + s (p1 - p0), onQ = q0 +
// t (q1 - q0). Zero-length segments are points; parallel segments give s at the first
// point of P that has a closest partner, so the answer is the same every time.
void pfxClosestPointsSegmentSegment(const PfxVector3& p0, const PfxVector3& p1,
                                    const PfxVector3& q0, const PfxVector3& q1, PfxFloat& s,
                                    PfxFloat& t, PfxVector3& onP, PfxVector3& onQ);

// The touching points of two edges that a separating-axis test found `separation` apart
// along `axis` (unit, from P to Q): their closest points, and the distance between them
// along the axis. False when those points do not lie on the axis at that separation within
// `mergeDistance` (plus a relative 1e-4), which happens when the edges' lines cross beyond
// an end; a face contact then describes the pair.
bool pfxEdgeContactPoints(const PfxVector3& p0, const PfxVector3& p1, const PfxVector3& q0,
                          const PfxVector3& q1, const PfxVector3& axis, PfxFloat separation,
                          PfxFloat mergeDistance, PfxVector3& onP, PfxVector3& onQ,
                          PfxFloat& distance);

// Parameter in [0, 1] of the point of segment p0-p1 closest to `point`.
PfxFloat pfxClosestParameterOnSegment(const PfxVector3& p0, const PfxVector3& p1,
                                      const PfxVector3& point);

}  // namespace pfx
