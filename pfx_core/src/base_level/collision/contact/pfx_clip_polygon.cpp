#include "base_level/collision/contact/pfx_clip_polygon.h"

namespace pfx {

PfxUInt32 pfxClipPolygonByPlane(const PfxVector3* in, PfxUInt32 numIn, const PfxVector3& normal,
                                PfxFloat offset, PfxVector3* out, PfxUInt32 capacity) {
  if (numIn == 0 || capacity == 0) return 0;
  if (numIn == 1) {
    if (normal.dot(in[0]) > offset) return 0;
    out[0] = in[0];
    return 1;
  }
  // A segment is a polygon whose closing edge is not walked again.
  const PfxUInt32 numEdges = numIn == 2 ? 1 : numIn;
  PfxUInt32 numOut = 0;
  const auto push = [&](const PfxVector3& p) {
    if (numOut < capacity) out[numOut++] = p;
  };
  if (numIn == 2 && normal.dot(in[0]) - offset <= 0) push(in[0]);
  for (PfxUInt32 i = 0; i < numEdges; ++i) {
    const PfxVector3& a = in[i];
    const PfxVector3& b = in[(i + 1) % numIn];
    const PfxFloat da = normal.dot(a) - offset;
    const PfxFloat db = normal.dot(b) - offset;
    if ((da < 0 && db > 0) || (da > 0 && db < 0)) push(a + (b - a) * (da / (da - db)));
    if (db <= 0) push(b);
  }
  return numOut;
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
