// Stage: a bounding volume hierarchy over broadphase proxies, for rays.
//
// The seed's walk over sorted proxy arrays (pfx_cast_rays.h) visits every proxy that
// begins before the ray's end along its dominant axis, also those far beside or behind
// the ray: among 1,000 bodies a 30 m ray visits hundreds. A hierarchy lets the ray visit
// only the boxes around its path. It is built from one proxy array in O(n log n), about
// what sorting the six arrays costs, and keeps the proxies' 16-bit boxes, so a node is 16
// bytes. pfxCastSingleRay and pfxCastRays descend it when PfxRayCastParam names it and
// give the same answers as the walk (the same closest hit, the same tie rule).
#pragma once

#include "pfx/base_level/broadphase/pfx_broadphase_proxy.h"

namespace pfx {

// Nodes are stored depth first: an inner node's first child follows it, m_link names the
// second. A leaf's m_link is PFX_RAY_BVH_LEAF | the index of its proxy in the array the
// hierarchy was built over.
struct PfxRayBvhNode {
  PfxUInt16 m_min[3];
  PfxUInt16 m_max[3];
  PfxUInt32 m_link;
};

constexpr PfxUInt32 PFX_RAY_BVH_LEAF = 0x80000000u;
// Proxies beyond this count cannot be named by a leaf.
constexpr PfxUInt32 PFX_RAY_BVH_MAX_PROXIES = PFX_RAY_BVH_LEAF;

// One leaf per proxy and one inner node per split.
inline PfxUInt32 pfxGetNumRayBvhNodes(PfxUInt32 numProxies) {
  return numProxies > 0 ? 2 * numProxies - 1 : 0;
}

PfxUInt32 pfxGetWorkBytesOfBuildRayBvh(PfxUInt32 numProxies);

struct PfxBuildRayBvhParam {
  void* workBuff = nullptr;  // 16-byte aligned, pfxGetWorkBytesOfBuildRayBvh bytes
  PfxUInt32 workBytes = 0;
  const PfxBroadphaseProxy* proxies = nullptr;  // any one array of pfxUpdateBroadphaseProxies
  PfxUInt32 numProxies = 0;
  PfxRayBvhNode* nodes = nullptr;  // pfxGetNumRayBvhNodes(numProxies) of them
  PfxUInt32 maxNodes = 0;
};

// Splits at the median of the proxies' centres along the axis where the centres spread
// most, which bounds the depth by log2(n) + 1. Rejects missing arrays (PFX_ERR_NULL_POINTER
// for proxies or nodes, PFX_ERR_OUT_OF_BUFFER for a short node or work buffer, with
// PFX_ERR_INVALID_ALIGNMENT for a misaligned work buffer), more proxies than
// PFX_RAY_BVH_MAX_PROXIES (PFX_ERR_OUT_OF_RANGE) and buffers that share bytes
// (PFX_ERR_INVALID_VALUE); nothing is written then. Allocates nothing.
PfxInt32 pfxBuildRayBvh(const PfxBuildRayBvhParam& param);

}  // namespace pfx
