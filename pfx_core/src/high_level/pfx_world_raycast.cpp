// PfxWorld's raycasts (seed chapter 5) and contact queries: proxies and the hierarchy over
// them, built on demand.
#include "pfx/high_level/pfx_world.h"

namespace pfx {

PfxInt32 PfxWorld::updateRayProxies() {
  if (!m_rayProxiesStale) return PFX_OK;
  const PfxUInt32 numBodies = getNumRigidBodies();
  // Sized by the bodies' capacity, as the other buffers are, so that casts between body
  // additions do not allocate.
  if (m_rayProxyStride < m_states.capacity()) {
    m_rayProxyStride = m_states.capacity();
    m_rayProxies.resize(2 * m_rayProxyStride);
    m_rayBvh.resize(pfxGetNumRayBvhNodes(static_cast<PfxUInt32>(m_rayProxyStride)));
  }
  m_numRayProxies = 0;
  if (numBodies > 0) {
    PfxBroadphaseProxy* proxies = m_rayProxies.data();
    PfxBroadphaseProxy* work = proxies + m_rayProxyStride;
    PfxUpdateBroadphaseProxiesParam param;
    param.workBuff = work;
    param.workBytes = pfxGetWorkBytesOfUpdateBroadphaseProxies(numBodies);
    param.offsetRigidStates = m_states.data();
    param.offsetCollidables = m_collidables.data();
    param.numRigidBodies = numBodies;
    param.skipBodies = skippedBodies();
    param.proxiesX = proxies;
    param.worldCenter = m_param.worldCenter;
    param.worldExtent = m_param.worldExtent;
    // Rays see every body as it is: none is dropped or fixed for lying outside the world,
    // and bounds are not swept along velocities.
    param.outOfWorldBehavior = 0;
    param.timeStep = 0;
    PfxUpdateBroadphaseProxiesResult result;
    // Fails only on a body whose state went bad (a simulation that blew up to NaN); the
    // proxies then stay stale and the cast reports it.
    if (const PfxInt32 err = pfxUpdateBroadphaseProxies(param, result, &m_taskManager);
        err != PFX_OK) {
      return err;
    }
    // The sort's scratch is free again and four times larger than the build needs.
    PfxBuildRayBvhParam bvhParam;
    bvhParam.workBuff = work;
    bvhParam.workBytes = pfxGetWorkBytesOfBuildRayBvh(result.numProxies);
    bvhParam.proxies = proxies;
    bvhParam.numProxies = result.numProxies;
    bvhParam.nodes = m_rayBvh.data();
    bvhParam.maxNodes = static_cast<PfxUInt32>(m_rayBvh.size());
    if (const PfxInt32 err = pfxBuildRayBvh(bvhParam); err != PFX_OK) return err;
    m_numRayProxies = result.numProxies;
  }
  updateParticleRayBounds();
  m_rayProxiesStale = false;
  return PFX_OK;
}

PfxRayCastParam PfxWorld::rayCastParam() const {
  PfxRayCastParam param;
  param.offsetRigidStates = m_states.data();
  param.offsetCollidables = m_collidables.data();
  param.numProxies = m_numRayProxies;
  param.rangeCenter = m_param.worldCenter;
  param.rangeExtent = m_param.worldExtent;
  if (m_numRayProxies > 0) {
    param.bvhNodes = m_rayBvh.data();
    param.bvhProxies = m_rayProxies.data();
  }
  return param;
}

PfxInt32 PfxWorld::castRay(const PfxRayInput& in, PfxRayOutput& out) {
  if (const PfxInt32 err = updateRayProxies(); err != PFX_OK) return err;
  const PfxRayInput ray = in;  // `out` may be the same memory
  if (const PfxInt32 err = pfxCastSingleRay(ray, out, rayCastParam()); err != PFX_OK) return err;
  castParticleRay(ray, out);
  return PFX_OK;
}

PfxInt32 PfxWorld::castRays(const PfxRayInput* in, PfxRayOutput* out, PfxUInt32 numRays) {
  if (const PfxInt32 err = updateRayProxies(); err != PFX_OK) return err;
  PfxRayCastParam param = rayCastParam();
  // Fewer rays share too little of their paths for the order to pay for the sort.
  constexpr PfxUInt32 kMinOrderedRays = 64;
  if (numRays >= kMinOrderedRays && numRays <= PFX_CAST_RAYS_MAX_ORDERED && in && out) {
    const std::size_t records = pfxGetWorkBytesOfCastRays(numRays) / sizeof(PfxSortData16);
    if (m_rayOrderWork.size() < records) m_rayOrderWork.resize(records);
    param.workBuff = m_rayOrderWork.data();
    param.workBytes = pfxGetWorkBytesOfCastRays(numRays);
  }
  if (const PfxInt32 err = pfxCastRays(in, out, numRays, param, &m_taskManager); err != PFX_OK) {
    return err;
  }
  if (m_particleGroups.empty()) return PFX_OK;
  // The rays were checked by pfxCastRays; each writes only its own output.
  constexpr PfxUInt32 kRaysPerTask = 64;
  return pfxParallelFor(&m_taskManager, numRays, kRaysPerTask,
                        [&](PfxUInt32 begin, PfxUInt32 end) {
                          for (PfxUInt32 i = begin; i < end; ++i) castParticleRay(in[i], out[i]);
                        });
}

PfxInt32 PfxWorld::queryContacts(const PfxContactQueryInput& query, PfxQueryContact* out,
                                 PfxUInt32 maxContacts, PfxQueryContactsResult& result) {
  if (const PfxInt32 err = updateRayProxies(); err != PFX_OK) return err;
  const PfxRayCastParam rays = rayCastParam();
  PfxQueryContactsParam param;
  param.offsetRigidStates = rays.offsetRigidStates;
  param.offsetCollidables = rays.offsetCollidables;
  param.bvhNodes = rays.bvhNodes;
  param.bvhProxies = rays.bvhProxies;
  param.numProxies = rays.numProxies;
  param.rangeCenter = rays.rangeCenter;
  param.rangeExtent = rays.rangeExtent;
  return pfxQueryContacts(query, param, out, maxContacts, result);
}

}  // namespace pfx
