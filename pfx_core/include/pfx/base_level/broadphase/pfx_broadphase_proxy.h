// One rigid body as the broad phase sees it: its bounding box quantized to 16 bits inside
// the world's bounds, its id, motion type, sleep flag and contact filters (seed chapter 2).
// A proxy is a PfxSortData32 so that pfxParallelSort orders proxy arrays directly. Its key
// packs, from the top: the 16-bit sort value of the array it is in, the 32-bit rigid body
// id (so that ties sort deterministically), then the motion type and the sleep flag.
#pragma once

#include "pfx/base_level/base/pfx_sort_data.h"
#include "pfx/base_level/rigidbody/pfx_motion_type.h"

namespace pfx {

using PfxBroadphaseProxy = PfxSortData32;

inline PfxUInt16 pfxGetXMin(const PfxBroadphaseProxy& p, int axis) {
  return static_cast<PfxUInt16>(p.data[axis >> 1] >> ((axis & 1) * 16));
}
inline PfxUInt16 pfxGetXMax(const PfxBroadphaseProxy& p, int axis) {
  const int i = axis + 3;
  return static_cast<PfxUInt16>(p.data[i >> 1] >> ((i & 1) * 16));
}
inline PfxUInt32 pfxGetObjectId(const PfxBroadphaseProxy& p) {
  return static_cast<PfxUInt32>(p.key >> 16);
}
inline PfxMotionType pfxGetMotionType(const PfxBroadphaseProxy& p) {
  return static_cast<PfxMotionType>(p.key & 0xff);
}
inline bool pfxGetSleeping(const PfxBroadphaseProxy& p) { return ((p.key >> 8) & 1) != 0; }
inline PfxUInt32 pfxGetSelf(const PfxBroadphaseProxy& p) { return p.data[3]; }
inline PfxUInt32 pfxGetTarget(const PfxBroadphaseProxy& p) { return p.data[4]; }
inline PfxUInt16 pfxGetSortValue(const PfxBroadphaseProxy& p) {
  return static_cast<PfxUInt16>(p.key >> 48);
}

inline void pfxSetXMin(PfxBroadphaseProxy& p, int axis, PfxUInt16 v) {
  const int shift = (axis & 1) * 16;
  PfxUInt32& word = p.data[axis >> 1];
  word = (word & ~(0xffffu << shift)) | (PfxUInt32(v) << shift);
}
inline void pfxSetXMax(PfxBroadphaseProxy& p, int axis, PfxUInt16 v) {
  const int i = axis + 3;
  const int shift = (i & 1) * 16;
  PfxUInt32& word = p.data[i >> 1];
  word = (word & ~(0xffffu << shift)) | (PfxUInt32(v) << shift);
}
inline void pfxSetIdentity(PfxBroadphaseProxy& p, PfxUInt32 id, PfxMotionType type,
                           bool sleeping) {
  p.key = (p.key & (PfxUInt64(0xffff) << 48)) | (PfxUInt64(id) << 16) |
          (sleeping ? 0x100u : 0u) | type;
}
inline void pfxSetSelf(PfxBroadphaseProxy& p, PfxUInt32 f) { p.data[3] = f; }
inline void pfxSetTarget(PfxBroadphaseProxy& p, PfxUInt32 f) { p.data[4] = f; }
inline void pfxSetSortValue(PfxBroadphaseProxy& p, PfxUInt16 v) {
  p.key = (p.key & ~(PfxUInt64(0xffff) << 48)) | (PfxUInt64(v) << 48);
}

inline bool pfxProxiesOverlap(const PfxBroadphaseProxy& a, const PfxBroadphaseProxy& b) {
  for (int axis = 0; axis < 3; ++axis) {
    if (pfxGetXMax(a, axis) < pfxGetXMin(b, axis) || pfxGetXMax(b, axis) < pfxGetXMin(a, axis)) {
      return false;
    }
  }
  return true;
}

}  // namespace pfx
