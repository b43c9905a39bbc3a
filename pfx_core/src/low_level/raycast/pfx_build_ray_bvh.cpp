#include "pfx/low_level/raycast/pfx_build_ray_bvh.h"

#include <algorithm>

#include "low_level/pfx_buffer_checks.h"

namespace pfx {

namespace {

class RayBvhBuilder {
 public:
  RayBvhBuilder(const PfxBroadphaseProxy* proxies, PfxUInt32* order, PfxRayBvhNode* nodes)
      : m_proxies(proxies), m_order(order), m_nodes(nodes) {}

  // Writes the subtree over m_order[begin, end) from the next free node on; returns its root.
  PfxUInt32 build(PfxUInt32 begin, PfxUInt32 end) {
    const PfxUInt32 index = m_next++;
    PfxUInt16 lo[3] = {0xffff, 0xffff, 0xffff};
    PfxUInt16 hi[3] = {0, 0, 0};
    PfxUInt32 centreLo[3] = {0xffffffffu, 0xffffffffu, 0xffffffffu};
    PfxUInt32 centreHi[3] = {0, 0, 0};
    for (PfxUInt32 i = begin; i < end; ++i) {
      const PfxBroadphaseProxy& proxy = m_proxies[m_order[i]];
      for (int a = 0; a < 3; ++a) {
        lo[a] = std::min(lo[a], pfxGetXMin(proxy, a));
        hi[a] = std::max(hi[a], pfxGetXMax(proxy, a));
        const PfxUInt32 c = centre(m_order[i], a);
        centreLo[a] = std::min(centreLo[a], c);
        centreHi[a] = std::max(centreHi[a], c);
      }
    }
    PfxRayBvhNode& node = m_nodes[index];
    for (int a = 0; a < 3; ++a) {
      node.m_min[a] = lo[a];
      node.m_max[a] = hi[a];
    }
    if (end - begin == 1) {
      node.m_link = PFX_RAY_BVH_LEAF | m_order[begin];
      return index;
    }
    int axis = 0;
    for (int a = 1; a < 3; ++a) {
      if (centreHi[a] - centreLo[a] > centreHi[axis] - centreLo[axis]) axis = a;
    }
    const PfxUInt32 mid = begin + (end - begin) / 2;
    // Ties broken by proxy index, so that the same proxies give the same tree anywhere.
    std::nth_element(m_order + begin, m_order + mid, m_order + end,
                     [this, axis](PfxUInt32 a, PfxUInt32 b) {
                       const PfxUInt32 ca = centre(a, axis), cb = centre(b, axis);
                       return ca < cb || (ca == cb && a < b);
                     });
    build(begin, mid);
    const PfxUInt32 second = build(mid, end);
    m_nodes[index].m_link = second;
    return index;
  }

 private:
  // Twice the centre, in cells: exact in integers.
  PfxUInt32 centre(PfxUInt32 proxyIndex, int axis) const {
    const PfxBroadphaseProxy& proxy = m_proxies[proxyIndex];
    return PfxUInt32(pfxGetXMin(proxy, axis)) + pfxGetXMax(proxy, axis);
  }

  const PfxBroadphaseProxy* m_proxies;
  PfxUInt32* m_order;
  PfxRayBvhNode* m_nodes;
  PfxUInt32 m_next = 0;
};

}  // namespace

PfxUInt32 pfxGetWorkBytesOfBuildRayBvh(PfxUInt32 numProxies) {
  return static_cast<PfxUInt32>(pfxAlignBytes(sizeof(PfxUInt32) * std::size_t(numProxies)));
}

PfxInt32 pfxBuildRayBvh(const PfxBuildRayBvhParam& param) {
  const PfxUInt32 n = param.numProxies;
  if (n == 0) return PFX_OK;
  const PfxParamNames at{"pfxBuildRayBvh", "PfxBuildRayBvhParam"};
  if (n > PFX_RAY_BVH_MAX_PROXIES) {
    return pfxRejectParam(PFX_ERR_OUT_OF_RANGE,
                          "pfxBuildRayBvh: PfxBuildRayBvhParam::numProxies is %u, more than "
                          "PFX_RAY_BVH_MAX_PROXIES (%u)",
                          n, PFX_RAY_BVH_MAX_PROXIES);
  }
  if (const PfxInt32 err = pfxCheckRequired(
          at, {{param.proxies, "proxies"}, {param.nodes, "nodes"}}, "numProxies", n);
      err != PFX_OK) {
    return err;
  }
  const PfxUInt32 numNodes = pfxGetNumRayBvhNodes(n);
  if (param.maxNodes < numNodes) {
    return pfxRejectParam(PFX_ERR_OUT_OF_BUFFER,
                          "pfxBuildRayBvh: PfxBuildRayBvhParam::maxNodes is %u; "
                          "pfxGetNumRayBvhNodes asks %u",
                          param.maxNodes, numNodes);
  }
  const PfxUInt64 orderBytes = PfxUInt64(sizeof(PfxUInt32)) * n;
  if (const PfxInt32 err =
          pfxCheckBuffer(at, "workBuff", param.workBuff, param.workBytes, orderBytes);
      err != PFX_OK) {
    return err;
  }
  const PfxUInt64 nodeBytes = PfxUInt64(sizeof(PfxRayBvhNode)) * numNodes;
  const PfxUInt64 proxyBytes = PfxUInt64(sizeof(PfxBroadphaseProxy)) * n;
  if (pfxRangesOverlap(param.nodes, nodeBytes, param.workBuff, orderBytes) ||
      pfxRangesOverlap(param.nodes, nodeBytes, param.proxies, proxyBytes) ||
      pfxRangesOverlap(param.workBuff, orderBytes, param.proxies, proxyBytes)) {
    return pfxRejectParam(PFX_ERR_INVALID_VALUE,
                          "pfxBuildRayBvh: PfxBuildRayBvhParam::nodes, workBuff and proxies share "
                          "bytes");
  }
  PfxUInt32* order = static_cast<PfxUInt32*>(param.workBuff);
  for (PfxUInt32 i = 0; i < n; ++i) order[i] = i;
  RayBvhBuilder(param.proxies, order, param.nodes).build(0, n);
  return PFX_OK;
}

}  // namespace pfx
