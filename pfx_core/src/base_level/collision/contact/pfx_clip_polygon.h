// Sutherland-Hodgman clipping of a convex polygon (or a segment, or a point) by a plane.
#pragma once

#include "pfx/base_level/base/pfx_vec_math.h"

namespace pfx {

// Enough for any face of a convex mesh clipped by the side planes of another face, and for
// a cylinder cap clipped by a box face.
constexpr PfxUInt32 PFX_MAX_CLIP_VERTICES = 2 * PFX_CONVEX_MESH_MAX_VERTICES + 4;

// Keeps the part of the polygon in[0..numIn) with dot(normal, p) <= offset and writes it to
// out (at most `capacity` points; `out` must not alias `in`). Two points are a segment and
// stay two points at most; one point is kept or dropped. Returns the number written.
PfxUInt32 pfxClipPolygonByPlane(const PfxVector3* in, PfxUInt32 numIn, const PfxVector3& normal,
                                PfxFloat offset, PfxVector3* out, PfxUInt32 capacity);

// The same for the plane whose normal is `direction` (+1 or -1) times the unit vector of
// `axis`: the signed distance is one product, where a general normal costs a dot product, and
// it is the same float the general routine gives for that normal.
PfxUInt32 pfxClipPolygonByAxisPlane(const PfxVector3* in, PfxUInt32 numIn, int axis,
                                    PfxFloat direction, PfxFloat offset, PfxVector3* out,
                                    PfxUInt32 capacity);

}  // namespace pfx

namespace pfx {

// The point of the convex polygon `incident` that comes nearest to the convex polygon
// `reference` seen along the unit `normal` (their distance measured across it); of the
// points as near to within `tolerance`, the deepest (smallest along `normal`). Meant for
// polygons that clipping showed to meet at most on their rims: a vertex of one inside the
// other is measured to that other's rim, not taken as zero.
PfxVector3 pfxNearestPointAcross(const PfxVector3* incident, PfxUInt32 numIncident,
                                 const PfxVector3* reference, PfxUInt32 numReference,
                                 const PfxVector3& normal, PfxFloat tolerance);

// Drops points within `tolerance` of an earlier point and returns how many remain: a face
// of zero size clips to copies of one point, which are one contact.
PfxUInt32 pfxRemoveDuplicatePoints(PfxVector3* points, PfxUInt32 count, PfxFloat tolerance);

}  // namespace pfx
