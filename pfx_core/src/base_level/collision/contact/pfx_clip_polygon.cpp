#include "base_level/collision/contact/pfx_clip_polygon.h"

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
